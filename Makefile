# DB-DTC PMSM drive firmware for the TMS320F28335: host build, tests,
# portability gates, SIL and the target build. See README.md.
#
#   make test       all unit and SIL tests, then again under ASan/UBSan
#   make sil        the paper's scenarios in SIL: CSV, plots, metrics report
#   make check      portability and static gates (float-only, 16-bit int, cppcheck)
#   make help       every target, one line each (the "## " text on its rule)

SHELL := /bin/bash
.DEFAULT_GOAL := all
.DELETE_ON_ERROR:

BUILD   ?= build
VARIANT ?= host
# `make campaign OUT=DIR` names the campaign's directory (tools/drivekit/campaign.mk), not the build's.
CAMPAIGN_OUT := $(if $(filter command line,$(origin OUT)),$(OUT))
override OUT := $(BUILD)/$(VARIANT)

CC ?= gcc
ifeq ($(origin CC),default)
CC := gcc
endif
AR ?= ar

# OPT compiles every object of the variant; LDOPT links the tests,
# PROG_LDOPT the programs (drive_sil, sil_bench).
ifeq ($(VARIANT),san)
OPT        := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
LDOPT      := -fsanitize=address,undefined
PROG_LDOPT := $(LDOPT)
else ifeq ($(VARIANT),o2)
# `make bench-ctrl`: the controller's cost as documented, at plain -O2.
OPT        := -O2 -g
LDOPT      :=
PROG_LDOPT :=
else
# The host build: -O3; objects carry machine code and GIMPLE (fat LTO), the
# tests link the machine code, the programs are optimised again across
# files at link time and linked statically (no dynamic loader: 0.25 ms
# less start-up). Results stay bit-identical to -O2: no -ffast-math,
# baseline x86-64 has no FMA and -std=c99 contracts nothing;
# -fno-math-errno lets libm built-ins (sqrt) skip their errno path.
OPT        := -O3 -g -fno-math-errno -flto=auto -ffat-lto-objects
LDOPT      := -fno-lto
PROG_LDOPT := -flto=auto -static
endif

# Warning sets. Portable sources (control/, firmware/, hal/f28335/) are
# float-only and must not use 8-bit types (forced include poisons them);
# the plant model under hal/sim/ and the tests may use double.
WARN_BASE     := -std=c99 -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes
FLOAT_ONLY    := -Wdouble-promotion -Wfloat-conversion -Wunsuffixed-float-constants
PORTABLE_INC  := -include control/c28x_portable.h
# Include lists, one per library: a layer sees itself and the layers below
# it only (control <- hal <- firmware <- tools/sil, tests see everything),
# and inside firmware/ a room itself and the rooms below it
# (firmware/rooms.mk); `make check` gates the same (tools/check/layers.sh).
include firmware/rooms.mk
include control/rooms.mk
# fw_upto ROOM: the rooms from the bottom up to ROOM
fw_upto        = $(call fw_upto_in,$1,$(FIRMWARE_ROOMS))
fw_upto_in     = $(firstword $2) $(if $(filter $1,$(firstword $2)),,$(call fw_upto_in,$1,$(wordlist 2,$(words $2),$2)))
INC_CONTROL   := $(addprefix -I,$(CONTROL_ROOMS))
INC_F28335    := -Ihal -Ihal/f28335 $(INC_CONTROL) -Itests/c2000_fake/include
INC_SIM       := -Ihal -Ihal/sim
INC_FW_ALL    := $(addprefix -Ifirmware/,$(FIRMWARE_ROOMS))
inc_firmware   = $(addprefix -Ifirmware/,$(call fw_upto,$1)) -Ihal -Ihal/f28335 $(INC_CONTROL)
INC_SILRUN    := -Itools/sil $(INC_FW_ALL) -Ihal -Ihal/sim -Ihal/f28335 $(INC_CONTROL)
INC           := $(INC_CONTROL) -Ihal $(INC_FW_ALL) -Ihal/sim -Itools/sil -Ihal/f28335 -Itests -Itests/c2000_fake/include

CF_CONTROL  := $(WARN_BASE) $(FLOAT_ONLY) -Wconversion $(PORTABLE_INC)
CF_PORTABLE := $(WARN_BASE) $(FLOAT_ONLY) $(PORTABLE_INC)
CF_SIM      := $(WARN_BASE) -Wfloat-conversion -D_POSIX_C_SOURCE=200809L
CF_TEST     := $(WARN_BASE) -Wno-missing-prototypes -D_POSIX_C_SOURCE=200809L

cflags_for = $(if $(filter control/%,$1),$(CF_CONTROL),$(if $(filter firmware/% hal/f28335/%,$1),$(CF_PORTABLE),$(if $(filter hal/sim/% tools/sil/%,$1),$(CF_SIM),$(CF_TEST))))
inc_for    = $(if $(filter control/%,$1),$(INC_CONTROL),$(if $(filter firmware/%,$1),$(call inc_firmware,$(word 2,$(subst /, ,$1))),$(if $(filter hal/f28335/% tests/c2000_fake/%,$1),$(INC_F28335),$(if $(filter hal/sim/%,$1),$(INC_SIM),$(if $(filter tools/sil/%,$1),$(INC_SILRUN),$(INC))))))

# Source groups, each archived into one static library, so a runner links
# only what it references. Fragments below add programs and test wiring.
CONTROL_SRCS  := $(foreach d,$(CONTROL_ROOMS),$(wildcard $d/*.c))
FIRMWARE_SRCS := $(filter-out firmware/f28335/main.c,$(wildcard firmware/*/*.c))
SIM_SRCS      := $(wildcard hal/sim/*.c)
SILRUN_SRCS   := tools/sil/scenario.c tools/sil/profile.c tools/sil/csv_num.c tools/sil/summary.c \
                 tools/sil/sil_board.c tools/sil/ini_edit.c tools/sil/json_out.c tools/sil/nv_file.c
F28335_SRCS   := $(wildcard hal/f28335/*.c) $(wildcard tests/c2000_fake/*.c)

objs = $(patsubst %.c,$(OUT)/obj/%.o,$1)

# make board's image (below): the target's sources against a motor file's configuration.
BOARD_OUT    ?= $(BUILD)/board
MOTOR        ?=
BOARD_CONFIG := $(BOARD_OUT)/drive_config.h
BOARD_SRCS   := $(CONTROL_SRCS) $(wildcard firmware/*/*.c) $(wildcard hal/f28335/*.c) $(wildcard tests/c2000_fake/*.c)
BOARD_OBJS   := $(patsubst %.c,$(BOARD_OUT)/obj/%.o,$(BOARD_SRCS))
BOARD_IMAGE  := $(BOARD_OUT)/drive_board

LIB_control  := $(OUT)/lib/libcontrol.a
LIB_firmware := $(OUT)/lib/libfirmware.a
LIB_sim      := $(OUT)/lib/libsim.a
LIB_silrun   := $(OUT)/lib/libsilrun.a
LIB_f28335   := $(OUT)/lib/libf28335.a

$(LIB_control):  $(call objs,$(CONTROL_SRCS))
$(LIB_firmware): $(call objs,$(FIRMWARE_SRCS))
$(LIB_sim):      $(call objs,$(SIM_SRCS))
$(LIB_silrun):   $(call objs,$(SILRUN_SRCS)) Makefile   # its list is written here: a new member rebuilds it
$(LIB_f28335):   $(call objs,$(F28335_SRCS))

$(OUT)/lib/%.a:
	@mkdir -p $(@D)
	@rm -f $@
	$(AR) rcs $@ $(filter %.o,$^)

# Objects are rebuilt when OPT changes (the stamp's text changes only then).
# -frandom-seed: the seed of the names in LTO sections from the source's path
# instead of a random one, so that a compile of the same source gives the
# same object to the byte and an unchanged drive_sil re-runs no scenario
# (`make sil`'s program stamp sums the objects).
OPT_STAMP := $(OUT)/obj/opt.stamp
$(OPT_STAMP): FORCE
	@mkdir -p $(@D)
	@echo '$(OPT)' | cmp -s - $@ || echo '$(OPT)' > $@

$(OUT)/obj/%.o: %.c $(OPT_STAMP) | host-deps
	@mkdir -p $(@D)
	$(CC) $(OPT) -frandom-seed=$< $(call cflags_for,$<) $(call inc_for,$<) -MMD -MP -c $< -o $@

# ---- tests ---------------------------------------------------------------
# Ceedling's convention: tests/test_<module>.c, one runner per file. A test
# links libcontrol by default; a fragment sets TEST_LIBS_test_<name> (in link
# order, e.g. "firmware sim control") and TEST_SRCS_test_<name> (extra
# sources such as mocks) when it needs more; the two common wirings:
#   $(call mock_tests,NAMES)  firmware/ against the HAL's cmocka mock
#   $(call sil_tests,NAMES)   sil_run() (tools/sil/sil.c) on the simulated board
TEST_SRCS  := $(wildcard tests/test_*.c)
TEST_NAMES := $(basename $(notdir $(TEST_SRCS)))
TEST_BINS  := $(addprefix $(OUT)/tests/,$(TEST_NAMES))
LDLIBS     := -lcmocka -linih -lm -pthread
PROG_LDLIBS := -linih -lm -pthread

test_libs = $(foreach l,$(or $(TEST_LIBS_$1),control),$(LIB_$l))
mock_tests = $(foreach t,$1,$(eval TEST_LIBS_$t := firmware control)$(eval TEST_SRCS_$t := tests/mock_hal.c))
sil_tests  = $(foreach t,$1,$(eval TEST_LIBS_$t := silrun firmware sim control)$(eval TEST_SRCS_$t := tools/sil/sil.c))

define TEST_RULE
$(OUT)/tests/$1: $(call objs,tests/$1.c $(TEST_SRCS_$1)) $(call test_libs,$1)
	@mkdir -p $$(@D)
	$$(CC) $$(OPT) $$(LDOPT) -o $$@ $$(filter %.o,$$^) $$(filter %.a,$$^) $$(LDLIBS)
endef

# ---- fragments -------------------------------------------------------------
-include $(wildcard control/module.mk firmware/module.mk hal/sim/module.mk tools/sil/module.mk hal/f28335/module.mk \
    tools/drivekit/module.mk tools/drivetool/module.mk tools/bench/module.mk tests/module.mk tests/cli/module.mk \
    tools/drivekit/campaign.mk)

$(foreach t,$(TEST_NAMES),$(eval $(call TEST_RULE,$t)))

.PHONY: all test test-host test-san run-tests check board firmware flash host-deps test-deps check-deps help clean distclean FORCE

all: $(TEST_BINS) $(HOST_PROGRAMS) ## the host build: every test runner, drive_sil and sil_bench

FORCE: ## (internal) a prerequisite that is never up to date

help: ## this list
	@echo 'Targets (README.md explains the main ones):'
	@tools/make/make_help.sh $(MAKEFILE_LIST)

# Debian packages the host build needs; installed when running as root.
# tools/make/ensure_pkgs.sh serialises its calls, so rules asking at once under
# -j wait for one another instead of racing apt.
host-deps: ## (internal) the Debian packages of the host build (as root: installs them)
	@tools/make/ensure_pkgs.sh gcc libcmocka-dev libinih-dev

# Everything `make test` installs, asked for once before its suites start.
TEST_PKGS := gcc libcmocka-dev libinih-dev clang libclang-rt-14-dev python3
test-deps: ## (internal) every package `make test` needs, asked for once before its suites
	@tools/make/ensure_pkgs.sh $(TEST_PKGS)

# Each suite records its counts here (tools/make/suite.sh); `make test` sums them.
RESULTS := $(BUILD)/test-results
suite    = tools/make/suite.sh $1 $(RESULTS)

run-tests: $(TEST_BINS) ## (internal) run the C test runners of VARIANT
	@$(call suite,test-$(VARIANT)) tools/make/run_tests.sh $(TEST_BINS)

test-host: ## the C unit and SIL tests (cmocka runners), host build
	@$(MAKE) --no-print-directory VARIANT=host run-tests

test-san: ## the same under ASan/UBSan (build/san)
	@$(MAKE) --no-print-directory VARIANT=san run-tests

# Every suite runs (-k) even when one fails; the last line on stdout is
# the verdict summed over all of them, and it sets the exit status.
TEST_SUITES = test-host test-san $(EXTRA_TESTS)
test: ## every suite (C, sanitizers, Python, CLI, fuzz pass, sweep nets); last line the summed verdict
	@rm -rf $(RESULTS)
	@$(MAKE) --no-print-directory test-deps
	@$(MAKE) --no-print-directory -k $(TEST_SUITES) || true
	@tools/make/test_verdict.sh $(RESULTS) $(TEST_SUITES)

# ---- portability and static gates ----------------------------------------
PORTABLE_DIRS := control firmware hal/f28335

check-deps: ## (internal) the cross compilers and cppcheck of `make check`
	@tools/make/ensure_pkgs.sh gcc-arm-none-eabi libnewlib-arm-none-eabi gcc-avr avr-libc cppcheck

# Commit subjects after this baseline are at most 72 characters (the
# history before it is left as it is).
COMMIT_BASELINE    := 73c655a
COMMIT_SUBJECT_MAX := 72

check: check-deps ## portability, layer, target-build, ISR-path, estimation-owner, tests' surface, RAM-budget, commit-subject and make-help gates
	@tools/check/commit_subjects.sh $(COMMIT_BASELINE) $(COMMIT_SUBJECT_MAX)
	@tools/make/make_help.sh --check $(MAKEFILE_LIST)
	@tools/check/portability.sh $(BUILD)/check
	@tools/check/target_cfg.sh
	@tools/check/isr_path.sh $(BUILD)/check
	@tools/check/est_owner.sh
	@tools/check/app_reach.sh
	@tools/check/ram_budget.sh $(BUILD)/check

# ---- cleaning --------------------------------------------------------------
# `make clean` keeps the Python venv: it is no build product of this tree's
# sources and takes a network download to make again.
clean: ## remove everything under build/ except the Python venv (build/venv)
	@test -n "$(BUILD)" && test "$(BUILD)" != / || { echo "make clean: BUILD='$(BUILD)' refused" >&2; exit 2; }
	@if [ -d "$(BUILD)" ]; then find "$(BUILD)" -mindepth 1 -maxdepth 1 ! -name venv -exec rm -rf {} +; fi

distclean: ## remove build/ entirely, the venv included
	@test -n "$(BUILD)" && test "$(BUILD)" != / || { echo "make distclean: BUILD='$(BUILD)' refused" >&2; exit 2; }
	rm -rf "$(BUILD)"

# ---- the board image from a motor file -------------------------------------
# make board MOTOR=FILE.ini: drive_sil resolves FILE as a run does (the
# bench's defaults for the keys a simulation defaults otherwise) and writes
# the image's configuration, $(BOARD_OUT)/drive_config.h and .json
# (tools/sil/board_config.h); the target's sources (control/, firmware/,
# hal/f28335/) are compiled against it on the host with the register fake
# and linked, main.c included. Without MOTOR: the board's own defaults.
# make firmware MOTOR=FILE.ini builds the same configuration with TI's tools.
# (The variables are set with the source groups above, for the fragments' rules.)
# Rewritten only when drive_sil's answer changes: an unchanged motor file compiles nothing again.
$(BOARD_CONFIG): $(DRIVE_SIL) FORCE
	@mkdir -p $(BOARD_OUT)/new
	@$(DRIVE_SIL) --scenario $(or $(MOTOR),/dev/null) --board-config $(BOARD_OUT)/new
	@for f in drive_config.h drive_config.json; do \
	    cmp -s $(BOARD_OUT)/new/$$f $(BOARD_OUT)/$$f || cp $(BOARD_OUT)/new/$$f $(BOARD_OUT)/$$f; done

$(BOARD_OUT)/obj/%.o: %.c $(BOARD_CONFIG) | host-deps
	@mkdir -p $(@D)
	@$(CC) -O2 $(call cflags_for,$<) $(call inc_for,$<) -DDRIVE_CONFIG -I$(BOARD_OUT) -MMD -MP -c $< -o $@

$(BOARD_IMAGE): $(BOARD_OBJS)
	@$(CC) -o $@ $^ -lm

board: $(BOARD_IMAGE) ## MOTOR=FILE.ini: the image's configuration (build/board/drive_config.h, .json), the target compiled against it on the host
	@echo "make board: $(BOARD_OUT)/drive_config.h and drive_config.json from $(or $(MOTOR),the board's defaults);" \
	    "$(words $(BOARD_OBJS)) target sources compiled against them and linked with the register fake ($(BOARD_IMAGE))"

# ---- target build --------------------------------------------------------
firmware: ## the F28335 image with TI's tools (needs CG_TOOL_ROOT and C2000WARE_ROOT; MOTOR=FILE.ini as make board)
	@tools/check/ti_tools.sh
	@$(if $(MOTOR),$(MAKE) --no-print-directory $(BOARD_CONFIG) MOTOR=$(MOTOR) &&) \
	    $(MAKE) --no-print-directory -f firmware/f28335/target.mk BUILD=$(BUILD) \
	    $(if $(MOTOR),DRIVE_CONFIG_DIR=$(BOARD_OUT))

flash: ## program the image with TI UniFlash (dslite.sh; MOTOR=FILE.ini: that image)
	@tools/check/ti_tools.sh
	@$(if $(MOTOR),$(MAKE) --no-print-directory $(BOARD_CONFIG) MOTOR=$(MOTOR) &&) \
	    $(MAKE) --no-print-directory -f firmware/f28335/target.mk flash BUILD=$(BUILD) \
	    $(if $(MOTOR),DRIVE_CONFIG_DIR=$(BOARD_OUT))

-include $(shell find $(OUT)/obj -name '*.d' 2>/dev/null)
-include $(shell find $(BOARD_OUT)/obj -name '*.d' 2>/dev/null)

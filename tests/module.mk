# tests/: the Python tests (tests/test_*.py) and the fuzz harnesses
# (tests/fuzz/, libFuzzer, clang from Debian); tests/cli/module.mk runs the
# command-line tests.
#   make test-tools  the Python tests; part of make test
#   make fuzz        >= FUZZ_STEPS ISR steps (default 10^8), corpus kept in build/fuzz/corpus
#   make fuzz-short  a seeded pass of a few seconds; part of make test
# Built with clang, ASan and UBSan (float-cast-overflow included), from the
# sources of control/ and firmware/ directly: the gcc build stays the
# warnings gate, so a clang-only warning does not fail the fuzz build.

FUZZ_DIR   := $(BUILD)/fuzz
FUZZ_BIN   := $(FUZZ_DIR)/fuzz_app
FUZZ_HARNESS := tests/fuzz/fuzz_app.c tests/fuzz/fuzz_hal.c
FUZZ_PORTABLE := $(CONTROL_SRCS) $(FIRMWARE_SRCS)
FUZZ_HDRS  := $(wildcard $(addsuffix /*.h,$(CONTROL_ROOMS)) firmware/*/*.h hal/hal.h hal/f28335/board_hw.h tests/fuzz/*.h) \
              tests/app_probe.h
FUZZ_CC    ?= clang
FUZZ_FLAGS := -std=c99 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
              -fno-omit-frame-pointer $(INC_CONTROL) -Ihal -Ihal/f28335 $(INC_FW_ALL) -Itests/fuzz
FUZZ_STEPS ?= 100000000

.PHONY: fuzz fuzz-short fuzz-deps
EXTRA_TESTS += fuzz-short

fuzz-deps: ## (internal) clang and its sanitizer runtime for the fuzzer
	@tools/make/ensure_pkgs.sh clang libclang-rt-14-dev

# The portable sources with their forced include (8-bit types poisoned), the harness without.
$(FUZZ_BIN): $(FUZZ_HARNESS) $(FUZZ_PORTABLE) $(FUZZ_HDRS) tests/module.mk | fuzz-deps
	@mkdir -p $(@D)/obj
	@set -e; for f in $(FUZZ_PORTABLE); do \
	    $(FUZZ_CC) $(FUZZ_FLAGS) -include control/c28x_portable.h -c $$f -o $(@D)/obj/$$(basename $$f .c).o; done
	$(FUZZ_CC) $(FUZZ_FLAGS) -o $@ $(FUZZ_HARNESS) $(patsubst %.c,$(@D)/obj/%.o,$(notdir $(FUZZ_PORTABLE))) -lm

fuzz: $(FUZZ_BIN) ## the control ISR under libFuzzer until FUZZ_STEPS ISR steps (10^8)
	@tests/fuzz/fuzz.sh long $(FUZZ_BIN) $(FUZZ_DIR) $(FUZZ_STEPS)

fuzz-short: $(FUZZ_BIN) ## (part of make test) a seeded fuzz pass of 4000 inputs
	@$(call suite,fuzz-short) tests/fuzz/fuzz.sh short $(FUZZ_BIN) $(FUZZ_DIR)

# The link's parser and dispatcher (tests/fuzz/fuzz_link.c), on the same
# objects as fuzz_app, then drive_sil --link's socket layer under random
# clients (tests/fuzz/fuzz_link_socket.py):
#   make fuzz-link        >= FUZZ_LINK_FRAMES framed requests (default 10^7), 2000 client actions
#   make fuzz-link-short  a seeded pass of a few seconds; part of make test
FUZZ_LINK_BIN    := $(FUZZ_DIR)/fuzz_link
FUZZ_LINK_FRAMES ?= 10000000
.PHONY: fuzz-link fuzz-link-short
EXTRA_TESTS += fuzz-link-short

$(FUZZ_LINK_BIN): tests/fuzz/fuzz_link.c tests/fuzz/fuzz_hal.c $(FUZZ_BIN)
	$(FUZZ_CC) $(FUZZ_FLAGS) -o $@ tests/fuzz/fuzz_link.c tests/fuzz/fuzz_hal.c \
	    $(patsubst %.c,$(FUZZ_DIR)/obj/%.o,$(notdir $(FUZZ_PORTABLE))) -lm

fuzz-link: $(FUZZ_LINK_BIN) $(DRIVE_SIL) ## the link's parser and dispatcher under libFuzzer until FUZZ_LINK_FRAMES frames (10^7), then drive_sil --link's sockets under 2000 random client actions
	@DRIVE_SIL=$(DRIVE_SIL) tests/fuzz/fuzz_link.sh long $(FUZZ_LINK_BIN) $(FUZZ_DIR)/link $(FUZZ_LINK_FRAMES)

fuzz-link-short: $(FUZZ_LINK_BIN) $(DRIVE_SIL) ## (part of make test) a seeded fuzz pass of the link, 3000 inputs, and 40 client actions on drive_sil --link's sockets
	@DRIVE_SIL=$(DRIVE_SIL) $(call suite,fuzz-link-short) tests/fuzz/fuzz_link.sh short $(FUZZ_LINK_BIN) $(FUZZ_DIR)/link

# The Python tests (tests/test_*.py: drivekit on hand-computed CSVs and
# its tables, drivetool, the check gates' parts) under the project's venv
# python (pyserial for drivetool's tests; sil_report imports matplotlib
# only to draw). No bytecode is written into the tree. test_sweep.py runs
# the built drive_sil (its summary against metrics), test_drivetool_sil.py
# drive_sil --link with the installed drivetool.
.PHONY: test-tools
EXTRA_TESTS += test-tools
test-tools: $(DRIVE_SIL) $(DRIVETOOL) ## (part of make test) the Python tools' unit tests, tests/test_*.py
	@DRIVE_SIL=$(DRIVE_SIL) DRIVETOOL=$(DRIVETOOL) PYTHONDONTWRITEBYTECODE=1 $(call suite,test-tools) \
	    $(VENV)/bin/python tools/make/run_py_tests.py tests

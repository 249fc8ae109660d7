# firmware/f28335/target.mk - the TMS320F28335 image, built with TI's cl2000.
#
#   make firmware CG_TOOL_ROOT=<ti-cgt-c2000> C2000WARE_ROOT=<C2000Ware> [MOTOR=FILE.ini]
#       -> $(BUILD)/f28335/drive.out (+ drive.map)
#   make -f firmware/f28335/target.mk flash CCXML=<target config> [UNIFLASH_ROOT=<uniflash>]
#
# Run through the top-level Makefile's `firmware` target, which first checks
# the tools (tools/check/ti_tools.sh). Sources: control/'s rooms (control/rooms.mk), the rooms'
# firmware/*/*.c (firmware/rooms.mk), hal/f28335/*.c,
# firmware/f28335/f28335_codestart.asm (the flash entry: watchdog
# off, .ebss zeroed), plus from C2000Ware the peripheral register
# definitions (DSP2833x_GlobalVariableDefs.c), the ADC trim routine's section
# (DSP2833x_ADC_cal.asm: ADC_cal lives in TI-reserved OTP) and the header
# linker command file. tools/check/target_cfg.sh (make check) checks the
# options and library names below against C2000Ware's F2833x projects.
# The host register fake (tests/c2000_fake) is never on this include path.

SHELL := /bin/bash
.DELETE_ON_ERROR:

include firmware/rooms.mk
include control/rooms.mk

BUILD ?= build
OUT   := $(BUILD)/f28335

CG_TOOL_ROOT   ?=
C2000WARE_ROOT ?=
# A motor file's configuration (make firmware MOTOR=FILE.ini: the top-level
# Makefile writes it with drive_sil --board-config): the directory of its
# drive_config.h, read through hal/f28335/board_hw.h; empty: the defaults.
DRIVE_CONFIG_DIR ?=
CL := $(CG_TOOL_ROOT)/bin/cl2000

F2833X_HEADERS := $(C2000WARE_ROOT)/device_support/f2833x/headers
F2833X_COMMON  := $(C2000WARE_ROOT)/device_support/f2833x/common
FASTRTS        := $(C2000WARE_ROOT)/libraries/math/FPUfastRTS/c28
# TI's Flash2833x API (SPRC539): the parameter store's writer
# (hal/f28335/hal_f28335_nv.c) calls it; f28335_flash.cmd runs it from RAM
# (Flash28_API) and names this library's file.
FLASH_API_ROOT ?= $(C2000WARE_ROOT)/libraries/flash_api/f2833x
FLASH_API_LIB  := Flash28335_API_V210.lib

# C28x + FPU32, COFF ABI (32-bit double, matching tools/check/c28x.xml),
# large memory model and unified memory as C2000Ware's f2833x headers expect.
CPU_FLAGS := -v28 -ml -mt --float_support=fpu32 --abi=coffabi
CFLAGS := $(CPU_FLAGS) --c99 --opt_level=2 --float_operations_allowed=32 \
          --diag_warning=225 --display_error_number \
          --preinclude=control/c28x_portable.h \
          --include_path=$(CG_TOOL_ROOT)/include \
          $(addprefix --include_path=,$(CONTROL_ROOMS)) --include_path=hal \
          $(addprefix --include_path=firmware/,$(FIRMWARE_ROOMS)) \
          --include_path=hal/f28335 \
          --include_path=$(F2833X_HEADERS)/include \
          --include_path=$(F2833X_COMMON)/include \
          --include_path=$(FASTRTS)/include \
          --include_path=$(FLASH_API_ROOT)/include \
          $(if $(DRIVE_CONFIG_DIR),--define=DRIVE_CONFIG --include_path=$(DRIVE_CONFIG_DIR))

# The ISR path runs from RAM. The control core (the directories in
# RAMFUNC_ALL) runs from RAM whole: every function of control/ is the ISR's
# or its set-up's, compiled --ramfunc=on, but for the files in
# RAMFUNC_ALL_EXCEPT: the commissioning's motor math (control/ident.c),
# which the ISR calls only in COMMISSION; control/'s configuration,
# start-up and naming files (smo_cfg.c, est_cfg.c, est_names.c,
# ctrl_cfg.c, dbdtc_cfg.c), which the background loop and the start
# sequence's transitions use; and the blocks whose set-up (init, cfg
# defaults, the start sequence's resets and starts, host-only entries)
# is large beside their per-period code (encoder.c, param_est.c,
# est_gate.c, psi_band.c, r_track.c, smo.c, rs_ident.c, est.c, pi.c,
# oplim.c): their ISR functions marked RAMFUNC, the set-up in flash
# (step 1's solve and its end stay in RAM: they share a period with
# ctrl_step). Elsewhere, and in those files,
# each function's definition says where it runs (control/c28x_portable.h):
# RAMFUNC in .TI.ramfunc (RAM), FLASHFUNC in flash on the ISR path on
# purpose (the start-up steps, commissioning and build levels: states that
# do not control the motor for the user; hal/f28335/README.md, "What runs
# from flash"), neither in flash off the ISR path. tools/check/isr_path.sh
# (make check) fails if a function the ISR reaches carries neither.
# (one line each: tools/check/placement.py reads them)
RAMFUNC_ALL := control
RAMFUNC_ALL_EXCEPT := control/ident.c control/encoder.c control/est/param_est.c control/est/est_gate.c control/est/psi_band.c control/est/r_track.c control/est/smo.c control/est/rs_ident.c control/est/est.c control/pi.c control/oplim.c control/est/smo_cfg.c control/est/est_cfg.c control/est/est_names.c control/ctrl/ctrl_cfg.c control/dbdtc_cfg.c

APP_SRCS  := $(foreach d,$(CONTROL_ROOMS),$(wildcard $d/*.c)) $(wildcard firmware/*/*.c) $(wildcard hal/f28335/*.c)
TI_C_SRCS := $(F2833X_HEADERS)/source/DSP2833x_GlobalVariableDefs.c
# The boot entry is ours (f28335_codestart.asm: watchdog off as C2000Ware's
# DSP2833x_CodeStartBranch.asm, then .ebss zeroed), not C2000Ware's.
APP_ASM_SRCS := firmware/f28335/f28335_codestart.asm
TI_ASM_SRCS := $(F2833X_COMMON)/source/DSP2833x_ADC_cal.asm

obj_of = $(OUT)/obj/$(basename $(notdir $1)).obj
APP_OBJS := $(foreach s,$(APP_SRCS),$(call obj_of,$s))
APP_OBJS += $(foreach s,$(APP_ASM_SRCS),$(call obj_of,$s))
TI_OBJS  := $(foreach s,$(TI_C_SRCS) $(TI_ASM_SRCS),$(call obj_of,$s))

# Linker: our memory map, then C2000Ware's peripheral-register placement.
# The FPU fast RTS supplement comes before the standard FPU32 RTS and
# --priority makes the first library that defines a symbol win, so
# sin/cos/atan2/sqrt and FS$$DIV resolve to it, not to the order the linker
# happens to search in. Its COFF objects are in
# rts2800_fpu32_fast_supplement_coff.lib (the plain .lib of current
# C2000Ware is an index whose members are only .libinfo files).
# --entry_point=code_start: a debugger load starts where the boot ROM's
# jump to flash does (f28335_codestart.asm: watchdog off, .ebss zeroed,
# then _c_int00), not at _c_int00 with the watchdog running through cinit.
LINK_CMDS := firmware/f28335/f28335_flash.cmd $(F2833X_HEADERS)/cmd/DSP2833x_Headers_nonBIOS.cmd
LFLAGS := -z --rom_model --entry_point=code_start --stack_size=0x400 --heap_size=0 \
          --warn_sections --reread_libs --priority \
          --search_path=$(CG_TOOL_ROOT)/lib --search_path=$(FASTRTS)/lib --search_path=$(FLASH_API_ROOT)/lib \
          --map_file=$(OUT)/drive.map
LIBS := --library=rts2800_fpu32_fast_supplement_coff.lib --library=rts2800_fpu32.lib --library=$(FLASH_API_LIB)

.PHONY: all flash flash-tools clean-target
all: $(OUT)/drive.out

$(OUT)/drive.out: $(APP_OBJS) $(TI_OBJS) $(LINK_CMDS)
	$(CL) $(CPU_FLAGS) $(LFLAGS) --output_file=$@ $(APP_OBJS) $(TI_OBJS) $(LINK_CMDS) $(LIBS)
	@echo "built $@ (map: $(OUT)/drive.map)"

# The compile options as a file that changes only with them: a build with
# another MOTOR (or none) compiles everything again.
CFLAGS_STAMP := $(OUT)/cflags.stamp
$(CFLAGS_STAMP): FORCE
	@mkdir -p $(@D)
	@echo '$(CFLAGS)' | cmp -s - $@ || echo '$(CFLAGS)' > $@
.PHONY: FORCE

# One object rule per source, so that files with equal names in different
# directories would collide loudly rather than silently.
define C_RULE
$(call obj_of,$1): $1 firmware/f28335/target.mk $(CFLAGS_STAMP)
	@mkdir -p $$(@D)
	$$(CL) $$(CFLAGS) $(if $(filter-out $(RAMFUNC_ALL_EXCEPT),$(filter $(addsuffix /%,$(RAMFUNC_ALL)),$1)),--ramfunc=on) \
	    --preproc_with_compile --preproc_dependency=$$(@:.obj=.d) \
	    --output_file=$$@ --compile_only $1
endef
define ASM_RULE
$(call obj_of,$1): $1 firmware/f28335/target.mk
	@mkdir -p $$(@D)
	$$(CL) $$(CPU_FLAGS) --output_file=$$@ --compile_only $1
endef
$(foreach s,$(APP_SRCS) $(TI_C_SRCS),$(eval $(call C_RULE,$s)))
$(foreach s,$(APP_ASM_SRCS) $(TI_ASM_SRCS),$(eval $(call ASM_RULE,$s)))

-include $(wildcard $(OUT)/obj/*.d)

# ---- flashing with TI UniFlash (command-line dslite) -----------------------
# CCXML: a target configuration for your debug probe + TMS320F28335
# (create it in CCS or UniFlash: File > New > Target Configuration).
UNIFLASH_ROOT ?=
DSLITE := $(or $(wildcard $(UNIFLASH_ROOT)/dslite.sh),$(shell command -v dslite.sh 2>/dev/null))
CCXML  ?=

# Tools are checked before anything is built (prerequisites run in order).
flash: flash-tools $(OUT)/drive.out
	"$(DSLITE)" --mode flash --config="$(CCXML)" -f -v "$(OUT)/drive.out"

flash-tools:
	@if [ -z "$(DSLITE)" ]; then \
	    echo "error: TI UniFlash's dslite.sh not found." >&2; \
	    echo "  Install UniFlash (ti.com/tool/UNIFLASH) and pass UNIFLASH_ROOT=<install dir>," >&2; \
	    echo "  or put dslite.sh on PATH, or flash $(OUT)/drive.out from CCS." >&2; \
	    exit 2; \
	fi
	@if [ -z "$(CCXML)" ] || [ ! -f "$(CCXML)" ]; then \
	    echo "error: CCXML='$(CCXML)' is not a target configuration file." >&2; \
	    echo "  Create one for your probe and the TMS320F28335 in CCS or UniFlash, then" >&2; \
	    echo "  make -f firmware/f28335/target.mk flash CCXML=path/to/f28335.ccxml" >&2; \
	    exit 2; \
	fi

clean-target:
	rm -rf $(OUT)

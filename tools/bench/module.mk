# tools/bench/module.mk - `make bench`: figures, printed, never judged (no
# timed tests). The SIL's speed (sil_bench), the controller's cost per
# ctrl_step() and per ISR period (callgrind, plain -O2: VARIANT=o2, its own
# build directory; the host build's -O3 and link-time optimisation would
# move them), sweep points per second, the link's ISR cost and B/s.
.PHONY: bench bench-ctrl bench-ctrl-deps bench-isr bench-link bench-sweep

SIL_BENCH := $(OUT)/sil_bench
HOST_PROGRAMS += $(SIL_BENCH)

$(SIL_BENCH): $(call objs,tools/bench/sil_bench.c tools/sil/sil.c) $(LIB_silrun) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) $(PROG_LDOPT) -o $@ $(filter %.o,$^) $(filter %.a,$^) $(PROG_LDLIBS)

bench: ## SIL speed, the controller's cost per ctrl_step() and per ISR period, sweep points and campaign draws per second, the link's ISR cost and B/s (printed)
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/sil_bench
	@$(BUILD)/host/sil_bench
	@$(MAKE) --no-print-directory VARIANT=host bench-ctrl
	@$(MAKE) --no-print-directory VARIANT=host bench-isr
	@$(MAKE) --no-print-directory VARIANT=host bench-sweep
	@$(MAKE) --no-print-directory VARIANT=host bench-campaign
	@$(MAKE) --no-print-directory VARIANT=host bench-link

# Linked without PIE so callgrind's addresses match objdump's.
$(OUT)/bench_ctrl: $(call objs,tools/bench/bench_ctrl.c) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) -no-pie -o $@ $(filter %.o,$^) $(filter %.a,$^) -lm

bench-ctrl-deps: ## (internal) valgrind and binutils for bench-ctrl
	@tools/make/ensure_pkgs.sh valgrind binutils

bench-ctrl: bench-ctrl-deps ## instructions, divisions, sqrt and sin/cos per ctrl_step() (callgrind, -O2)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/bench_ctrl
	@tools/bench/bench_ctrl.sh $(BUILD)/o2/bench_ctrl 20000

# The worst ISR period against the typical one over a run through every
# state (bench_isr.ini); a few minutes: one callgrind dump per period.
bench-isr: bench-ctrl-deps ## app_isr instructions per period, typical and worst per method (callgrind, -O2)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/drive_sil $(BUILD)/o2/bench_isr_link
	@BENCH_ISR_LINK=$(BUILD)/o2/bench_isr_link tools/bench/bench_isr.sh $(BUILD)/o2/drive_sil tools/bench/bench_isr.ini

# 1000 points (25 x 20 x 2 methods) of the paper's 1.2 s switching scenario.
bench-sweep: $(DRIVE_SIL) ## drive_sil x real time and sweep points per second (part of bench)
	@python3 tools/bench/bench_drive_sil.py $(DRIVE_SIL)
	@rm -rf $(OUT)/sweep_bench
	@$(SWEEP_PY) --quiet --grid controller.L_factor=0.5:2:25 --grid controller.psif_factor=0.5:2:20 \
	    --out $(OUT)/sweep_bench 2>&1 | sed -n 's/^sweep.py: \(.*points\/s.*\) ->.*/bench sweep 1000 points: \1/p'

# The link's figures: its cost in the control ISR (callgrind, plain -O2 as
# bench-ctrl) and the bytes per second drivetool gets from drive_sil --link
# at 115200 and 937500 baud (bench_link.py).
$(OUT)/bench_link: $(call objs,tools/bench/bench_link.c) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) -no-pie -o $@ $(filter %.o,$^) $(filter %.a,$^) -lm

# The ISR bench's run with the link busy (bench_isr.sh, BENCH_ISR_LINK).
$(OUT)/bench_isr_link: $(call objs,tools/bench/bench_isr_link.c tools/sil/sil.c) $(LIB_silrun) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) $(PROG_LDOPT) -o $@ $(filter %.o,$^) $(filter %.a,$^) $(PROG_LDLIBS)

bench-link: bench-ctrl-deps $(DRIVETOOL) ## link_isr's instructions per period, drivetool's B/s over drive_sil at 115200 and 937500 (part of bench)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/bench_link
	@tools/bench/bench_link.sh $(BUILD)/o2/bench_link 20000
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/drive_sil
	@$(VENV)/bin/python tools/bench/bench_link.py $(BUILD)/host/drive_sil

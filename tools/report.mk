# tools/report.mk - the SIL report and the controller's cost figures.
#   make sil-report   build/sil/report.md from the CSVs of `make sil`
#   make bench-ctrl   instructions, divisions, square roots and sin/cos per
#                     ctrl_step() (callgrind, x86-64 -O2); printed only
.PHONY: sil-report bench-ctrl bench-ctrl-deps

sil-report:
	@python3 tools/sil_report.py --dir $(BUILD)/sil

# Linked without PIE so callgrind's addresses match objdump's.
$(OUT)/bench_ctrl: $(call objs,tools/bench_ctrl.c) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) -no-pie -o $@ $(filter %.o,$^) $(filter %.a,$^) -lm

bench-ctrl-deps:
	@tools/ensure_pkgs.sh valgrind binutils

# Figures are for the default VARIANT=host build (-O2).
bench-ctrl: bench-ctrl-deps $(OUT)/bench_ctrl
	@tools/bench_ctrl.sh $(OUT)/bench_ctrl 20000

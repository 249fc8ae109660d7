# tools/report.mk - the SIL report and the controller's cost figures.
#   make sil-report   build/sil/report.md from the CSVs of `make sil`
#   make bench-ctrl   instructions, divisions, square roots and sin/cos per
#                     ctrl_step() (callgrind, x86-64 -O2); printed only
#   make bench-isr    app_isr's instructions per period, typical and worst,
#                     per method (callgrind, x86-64 -O2, tools/bench_isr.sh)
#   make test-tools   tests of the report's tools (tests/test_*.py: metrics.py
#                     on hand-computed CSVs, sil_report.py's tables); part of
#                     `make test`
.PHONY: sil-report bench-ctrl bench-ctrl-deps bench-isr test-tools

sil-report: ## rewrite build/sil/report.md from the runs there (system python3: tables only)
	@python3 tools/sil_report.py --dir $(BUILD)/sil

# Linked without PIE so callgrind's addresses match objdump's.
$(OUT)/bench_ctrl: $(call objs,tools/bench_ctrl.c) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) -no-pie -o $@ $(filter %.o,$^) $(filter %.a,$^) -lm

bench-ctrl-deps: ## (internal) valgrind and binutils for bench-ctrl
	@tools/ensure_pkgs.sh valgrind binutils

# Figures are for plain -O2 (VARIANT=o2, its own build directory; the
# host build's -O3 and link-time optimisation would move them).
bench-ctrl: bench-ctrl-deps ## instructions, divisions, sqrt and sin/cos per ctrl_step() (callgrind, -O2)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/bench_ctrl
	@tools/bench_ctrl.sh $(BUILD)/o2/bench_ctrl 20000

# The worst ISR period against the typical one over a run through every
# state (tools/bench_isr.ini); a few minutes: one callgrind dump per period.
bench-isr: bench-ctrl-deps ## app_isr instructions per period, typical and worst per method (callgrind, -O2)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/drive_sil $(BUILD)/o2/bench_isr_link
	@BENCH_ISR_LINK=$(BUILD)/o2/bench_isr_link tools/bench_isr.sh $(BUILD)/o2/drive_sil tools/bench_isr.ini

# Standard-library unittest under the project's venv python (pyserial
# for drivetool's tests; sil_report.py imports matplotlib only to draw).
# No bytecode is written into the tree.
EXTRA_TESTS += test-tools
# tests/test_sweep.py runs the built drive_sil (its summary against metrics.py);
# tests/test_drivetool_sil.py runs drive_sil --link with the installed drivetool.
test-tools: $(DRIVE_SIL) $(DRIVETOOL) ## (part of make test) the Python tools' unit tests, tests/test_*.py
	@DRIVE_SIL=$(DRIVE_SIL) DRIVETOOL=$(DRIVETOOL) PYTHONDONTWRITEBYTECODE=1 $(call suite,test-tools) \
	    $(VENV)/bin/python tools/run_py_tests.py tests

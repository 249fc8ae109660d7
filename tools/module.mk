# tools: `make bench` (SIL speed figures) and `make sil` (every scenario in
# tools/scenarios/*.ini through drive_sil, CSV and PNG into build/sil/).
# After the runs, tools/sil_report.py writes build/sil/report.md.

SIL_BENCH := $(OUT)/sil_bench
HOST_PROGRAMS += $(SIL_BENCH)

$(SIL_BENCH): $(call objs,tools/sil_bench.c tools/sil/sil.c) $(LIB_silrun) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) $(PROG_LDOPT) -o $@ $(filter %.o,$^) $(filter %.a,$^) $(PROG_LDLIBS)

.PHONY: bench sil

bench:
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/sil_bench
	@$(BUILD)/host/sil_bench
	@$(MAKE) --no-print-directory VARIANT=host bench-ctrl
	@$(MAKE) --no-print-directory VARIANT=host bench-sweep

SIL_DIR    := $(BUILD)/sil
VENV       := $(BUILD)/venv
VENV_STAMP := $(VENV)/.installed

# A fresh Debian python3 may lack ensurepip (package python3-venv).
$(VENV_STAMP): tools/requirements.txt
	@python3 -c 'import ensurepip' 2>/dev/null || tools/ensure_pkgs.sh python3-venv
	python3 -m venv $(VENV)
	$(VENV)/bin/python -m pip install -q -r tools/requirements.txt
	@touch $@

sil: $(VENV_STAMP)
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/drive_sil
	@mkdir -p $(SIL_DIR)
	@set -e; for f in tools/scenarios/*.ini; do \
	    n=$$(basename $$f .ini); \
	    $(BUILD)/host/drive_sil --scenario $$f --out $(SIL_DIR)/$$n.csv; \
	    $(VENV)/bin/python tools/sil_plot.py $(SIL_DIR)/$$n.csv $(SIL_DIR)/$$n.png; \
	done
	@$(VENV)/bin/python tools/sil_report.py --dir $(SIL_DIR)

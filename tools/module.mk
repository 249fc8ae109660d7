# tools: `make bench` (SIL speed figures) and `make sil` (every scenario in
# tools/scenarios/*.ini through drive_sil, CSV and PNG into build/sil/; the
# realistic ones again over SIL_SEEDS, summaries into build/sil/seeds/).
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
	@$(MAKE) --no-print-directory VARIANT=host bench-isr
	@$(MAKE) --no-print-directory VARIANT=host bench-sweep

SIL_DIR    := $(BUILD)/sil
# Noise seeds of the realistic runs' spread (report section "over noise seeds")
SIL_SEEDS  := 1 2 3 4 5 6 7 8
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
	@mkdir -p $(SIL_DIR)/seeds
	@set -e; for f in tools/scenarios/real_*.ini; do \
	    for s in $(SIL_SEEDS); do printf 'seed%s\tplant.seed=%s\n' $$s $$s; done | \
	        $(BUILD)/host/drive_sil --scenario $$f --batch > $(SIL_DIR)/seeds/$$(basename $$f .ini).jsonl; \
	done
	@$(VENV)/bin/python tools/sil_report.py --dir $(SIL_DIR)

# tools/ensure_pkgs.sh under -j: concurrent callers, one apt-get (fakes on PATH).
.PHONY: test-ensure-pkgs
EXTRA_TESTS += test-ensure-pkgs
test-ensure-pkgs:
	@$(call suite,test-ensure-pkgs) tools/test_ensure_pkgs.sh

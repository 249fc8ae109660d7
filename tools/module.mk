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
	@$(MAKE) --no-print-directory VARIANT=host bench-sweep
	@$(MAKE) --no-print-directory VARIANT=host bench-link

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

# drivetool (tools/drivetool/, the link's host tool) into the venv:
# build/venv/bin/drivetool. Installed from a copy, so pip's build leaves
# nothing in the source tree.
DRIVETOOL      := $(VENV)/bin/drivetool
DRIVETOOL_SRCS := $(wildcard tools/drivetool/pyproject.toml tools/drivetool/drivetool/*.py)
.PHONY: drivetool
drivetool: $(DRIVETOOL)
$(DRIVETOOL): $(VENV_STAMP) $(DRIVETOOL_SRCS)
	@rm -rf $(BUILD)/drivetool-src && mkdir -p $(BUILD)/drivetool-src
	@cp -r tools/drivetool/pyproject.toml tools/drivetool/drivetool $(BUILD)/drivetool-src/
	$(VENV)/bin/python -m pip install -q --no-deps $(BUILD)/drivetool-src
	@touch $@

# The link's figures (make bench): its cost in the control ISR (callgrind,
# plain -O2 as bench-ctrl) and the bytes per second drivetool gets from
# drive_sil --link at 115200 and 937500 baud (tools/bench_link.py).
$(OUT)/bench_link: $(call objs,tools/bench_link.c) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) -no-pie -o $@ $(filter %.o,$^) $(filter %.a,$^) -lm

.PHONY: bench-link
bench-link: bench-ctrl-deps $(DRIVETOOL)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/bench_link
	@tools/bench_link.sh $(BUILD)/o2/bench_link 20000
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/drive_sil
	@$(VENV)/bin/python tools/bench_link.py $(BUILD)/host/drive_sil

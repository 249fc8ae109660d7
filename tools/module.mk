# tools: `make bench` (SIL speed figures), `make sil` (below), the venv and
# `make plot`.

SIL_BENCH := $(OUT)/sil_bench
HOST_PROGRAMS += $(SIL_BENCH)

$(SIL_BENCH): $(call objs,tools/sil_bench.c tools/sil/sil.c) $(LIB_silrun) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) $(PROG_LDOPT) -o $@ $(filter %.o,$^) $(filter %.a,$^) $(PROG_LDLIBS)

.PHONY: bench sil sil-update sil-plots-update venv plot

bench: ## SIL speed, the controller's cost per ctrl_step() and per ISR period, sweep points and campaign draws per second, the link's ISR cost and B/s (printed)
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/sil_bench
	@$(BUILD)/host/sil_bench
	@$(MAKE) --no-print-directory VARIANT=host bench-ctrl
	@$(MAKE) --no-print-directory VARIANT=host bench-isr
	@$(MAKE) --no-print-directory VARIANT=host bench-sweep
	@$(MAKE) --no-print-directory VARIANT=host bench-link
	@$(MAKE) --no-print-directory VARIANT=host bench-campaign

# ---- the Python venv (matplotlib) and sil-plot --------------------------
VENV         := $(BUILD)/venv
VENV_STAMP   := $(VENV)/.installed
SIL_PLOT_BIN := $(VENV)/bin/sil-plot

# A fresh Debian python3 may lack ensurepip (package python3-venv).
$(VENV_STAMP): tools/requirements.txt
	@python3 -c 'import ensurepip' 2>/dev/null || tools/ensure_pkgs.sh python3-venv
	python3 -m venv $(VENV)
	$(VENV)/bin/python -m pip install -q -r tools/requirements.txt
	@touch $@

# sil-plot RUN.csv: tools/sil_plot.py on the venv's python (absolute paths:
# it runs from any directory).
$(SIL_PLOT_BIN): $(VENV_STAMP)
	@{ echo '#!/bin/sh'; \
	   echo '# sil-plot RUN.csv [-o OUT.png]: tools/sil_plot.py with the matplotlib of this venv'; \
	   echo 'exec "$(abspath $(VENV))/bin/python" "$(abspath tools/sil_plot.py)" "$$@"'; } > $@.tmp
	@chmod +x $@.tmp && mv $@.tmp $@

venv: $(SIL_PLOT_BIN) ## build/venv: matplotlib for the plots, and build/venv/bin/sil-plot

plot: $(SIL_PLOT_BIN) ## CSV=RUN.csv [PNG=OUT.png]: plot one drive_sil run (default RUN.png)
	@test -n "$(CSV)" || { echo "make plot: name the run: make plot CSV=RUN.csv [PNG=OUT.png]" >&2; exit 2; }
	@$(SIL_PLOT_BIN) "$(CSV)" $(if $(PNG),-o "$(PNG)")

# ---- make sil ------------------------------------------------------------
# Every tools/scenarios/*.ini through drive_sil into $(SIL_DIR)/<stem>.csv
# (and <stem>.resolved.json), its plot <stem>.png, the realistic ones
# (real_*) again over SIL_SEEDS into seeds/<stem>.jsonl (drive_sil --batch
# summaries), and report.md with its figures (tools/sil_report.py).
# Incremental: a run is redone when its scenario or drive_sil's code changed, a
# plot when its CSV or tools/sil_plot.py did, the report when any of
# them did (and its figures only for the runs that changed). One CSV and
# one seeds file per rule, so the runs go in parallel; `make sil` without
# -j runs its sub-make with -j$(SIL_JOBS). Plots of changed runs are drawn
# together by one tools/sil_plot.py with SIL_JOBS processes (one
# matplotlib start-up each, not one per plot): each out-of-date PNG's rule
# only queues its CSV. Exit status 3 of drive_sil (the run ended in FAULT)
# is a result, not an error.
SIL_DIR        := $(BUILD)/sil
# Noise seeds of the realistic runs' spread (report section "over noise seeds")
SIL_SEEDS      := 1 2 3 4 5 6 7 8
SIL_JOBS       ?= $(shell nproc)
# The program the runs use (tests/test_sil_make.py sets a fake), and what
# its results depend on: its link inputs but the revision string (a new
# commit relinks drive_sil with a new --version and the same code), and
# its link options. The runs depend on a stamp of their checksum.
SIL_PROG        := $(DRIVE_SIL)
SIL_PROG_INPUTS := $(filter-out $(call objs,$(SIL_VERSION_C)),$(DRIVE_SIL_INPUTS))
SIL_PROG_STAMP  := $(SIL_DIR)/.drive_sil.sum
SIL_SCENARIOS  := $(sort $(wildcard tools/scenarios/*.ini))
SIL_STEMS      := $(basename $(notdir $(SIL_SCENARIOS)))
SIL_CSVS       := $(SIL_STEMS:%=$(SIL_DIR)/%.csv)
SIL_PNGS       := $(SIL_STEMS:%=$(SIL_DIR)/%.png)
SIL_SEED_RUNS  := $(patsubst %,$(SIL_DIR)/seeds/%.jsonl,$(filter real_%,$(SIL_STEMS)))
SIL_REPORT     := $(SIL_DIR)/report.md
SIL_PLOT_QUEUE := $(SIL_DIR)/.plot-queue
# Stamps whose text changes only with the scenario list and SIL_SEEDS.
SIL_LIST_STAMP := $(SIL_DIR)/.scenarios
SIL_SEED_STAMP := $(SIL_DIR)/seeds/.seeds

sil: $(SIL_PLOT_BIN) ## every tools/scenarios/*.ini in SIL: CSV, plot, seeds and report.md into build/sil/ (only what changed)
	@$(MAKE) --no-print-directory VARIANT=host $(if $(filter -j%,$(MAKEFLAGS)),,-j$(SIL_JOBS)) sil-update

sil-update: $(SIL_REPORT) ## (inside `make sil`) bring build/sil/ up to date; needs VARIANT=host and the venv

$(SIL_PROG_STAMP): $(SIL_PROG)
	@mkdir -p $(@D)
	@sum="$$(cat $(SIL_PROG_INPUTS) | sha256sum) $(PROG_LDOPT) $(PROG_LDLIBS)"; \
	 echo "$$sum" | cmp -s - $@ || echo "$$sum" > $@

$(SIL_DIR)/%.csv: tools/scenarios/%.ini $(SIL_PROG_STAMP)
	@mkdir -p $(@D)
	@$(SIL_PROG) --scenario $< --out $@ || [ $$? -eq 3 ]

$(SIL_DIR)/%.png: $(SIL_DIR)/%.csv tools/sil_plot.py
	@echo $< >> $(SIL_PLOT_QUEUE)

# The queue's CSVs that still have a scenario (an interrupted run may have left others).
sil-plots-update: $(SIL_PNGS) ## (inside `make sil`) draw the queued plots of changed runs in one process pool
	@rm -f $(SIL_PLOT_QUEUE) $(if $(filter $(SIL_CSVS),$(file < $(SIL_PLOT_QUEUE))),; \
	    $(VENV)/bin/python tools/sil_plot.py --quiet --jobs $(SIL_JOBS) $(sort $(filter $(SIL_CSVS),$(file < $(SIL_PLOT_QUEUE)))) && \
	    echo "sil: $(words $(sort $(filter $(SIL_CSVS),$(file < $(SIL_PLOT_QUEUE))))) plots drawn")

$(SIL_SEED_STAMP): FORCE
	@mkdir -p $(@D)
	@echo '$(SIL_SEEDS)' | cmp -s - $@ || echo '$(SIL_SEEDS)' > $@

$(SIL_DIR)/seeds/%.jsonl: tools/scenarios/%.ini $(SIL_PROG_STAMP) $(SIL_SEED_STAMP)
	@for s in $(SIL_SEEDS); do printf 'seed%s\tplant.seed=%s\n' $$s $$s; done | \
	    $(SIL_PROG) --scenario $< --batch > $@.tmp && mv $@.tmp $@

# A scenario removed from tools/scenarios/ takes its results out of the report.
$(SIL_LIST_STAMP): FORCE
	@mkdir -p $(@D)
	@echo '$(SIL_STEMS)' | cmp -s - $@ || { \
	    for f in $(basename $(filter-out $(SIL_CSVS),$(wildcard $(SIL_DIR)/*.csv))); do \
	        rm -f $$f.csv $$f.resolved.json $$f.png $${f}_step1.png $(SIL_DIR)/seeds/$$(basename $$f).jsonl; \
	    done; echo '$(SIL_STEMS)' > $@; }

# A report naming runs it could not measure (exit 1) is kept to be read,
# dated 1970 so that the next `make sil` writes it again.
.PRECIOUS: $(SIL_REPORT)
$(SIL_REPORT): $(SIL_CSVS) $(SIL_SEED_RUNS) $(SIL_LIST_STAMP) tools/sil_report.py tools/metrics.py | sil-plots-update
	@$(VENV)/bin/python tools/sil_report.py --dir $(SIL_DIR) --jobs $(SIL_JOBS) || \
	 { touch -d @0 $@ 2> /dev/null; exit 1; }

# tools/ensure_pkgs.sh under -j: concurrent callers, one apt-get (fakes on PATH).
.PHONY: test-ensure-pkgs
EXTRA_TESTS += test-ensure-pkgs
test-ensure-pkgs: ## (part of make test) tools/ensure_pkgs.sh under -j, against a fake apt-get
	@$(call suite,test-ensure-pkgs) tools/test_ensure_pkgs.sh

# drivetool (tools/drivetool/, the link's host tool) into the venv:
# build/venv/bin/drivetool. Installed from a copy, so pip's build leaves
# nothing in the source tree.
DRIVETOOL      := $(VENV)/bin/drivetool
DRIVETOOL_SRCS := $(wildcard tools/drivetool/pyproject.toml tools/drivetool/drivetool/*.py)
.PHONY: drivetool
drivetool: $(DRIVETOOL) ## build/venv/bin/drivetool: the drive's link tool (tools/drivetool/README.md)
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

# The ISR bench's run with the link busy (tools/bench_isr.sh, BENCH_ISR_LINK).
$(OUT)/bench_isr_link: $(call objs,tools/bench_isr_link.c tools/sil/sil.c) $(LIB_silrun) $(LIB_firmware) $(LIB_sim) $(LIB_control)
	@mkdir -p $(@D)
	$(CC) $(OPT) $(PROG_LDOPT) -o $@ $(filter %.o,$^) $(filter %.a,$^) $(PROG_LDLIBS)

.PHONY: bench-link
bench-link: bench-ctrl-deps $(DRIVETOOL) ## link_isr's instructions per period, drivetool's B/s over drive_sil at 115200 and 937500 (part of bench)
	@$(MAKE) --no-print-directory VARIANT=o2 $(BUILD)/o2/bench_link
	@tools/bench_link.sh $(BUILD)/o2/bench_link 20000
	@$(MAKE) --no-print-directory VARIANT=host $(BUILD)/host/drive_sil
	@$(VENV)/bin/python tools/bench_link.py $(BUILD)/host/drive_sil

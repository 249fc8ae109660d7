# tools/drivekit/module.mk - the Python venv, drivekit (the report, plot,
# sweep and metrics tools: tools/drivekit/README.md) and the rules that run
# it: `make venv`, `make plot`, `make sil`, `make sil-report`, `make sweep`
# and the suites of `make test` that judge the method (sweep nets, the
# campaigns, the estimation's grids).

# ---- the Python venv (matplotlib) and drivekit's console scripts --------
VENV          := $(BUILD)/venv
VENV_STAMP    := $(VENV)/.installed
DRIVEKIT      := $(VENV)/.drivekit
DRIVEKIT_SRCS := $(wildcard tools/drivekit/pyproject.toml tools/drivekit/drivekit/*.py)
SIL_PLOT_BIN  := $(VENV)/bin/sil-plot
# drivekit's modules on the system python3 (standard library only; the
# suites of `make test` need no venv): $(call drivekit,MODULE) ARGS
drivekit       = env PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=tools/drivekit python3 -m drivekit.$1

# A fresh Debian python3 may lack ensurepip (package python3-venv).
$(VENV_STAMP): tools/drivekit/requirements.txt
	@python3 -c 'import ensurepip' 2>/dev/null || tools/make/ensure_pkgs.sh python3-venv
	python3 -m venv $(VENV)
	$(VENV)/bin/python -m pip install -q -r tools/drivekit/requirements.txt
	@touch $@

# drivekit into the venv: its console scripts (pyproject.toml) in
# build/venv/bin. Installed from a copy, so pip's build leaves nothing in
# the source tree; a new module is picked up by the wildcard above.
$(DRIVEKIT): $(VENV_STAMP) $(DRIVEKIT_SRCS)
	@rm -rf $(BUILD)/drivekit-src && mkdir -p $(BUILD)/drivekit-src
	@cp -r tools/drivekit/pyproject.toml tools/drivekit/drivekit $(BUILD)/drivekit-src/
	$(VENV)/bin/python -m pip install -q --no-deps $(BUILD)/drivekit-src
	@touch $@

.PHONY: venv plot sil sil-update sil-plots-update sil-report sweep

venv: $(DRIVEKIT) ## build/venv: matplotlib, and drivekit's console scripts (sil-plot, sil-report, sil-metrics, ...)

plot: $(DRIVEKIT) ## CSV=RUN.csv [PNG=OUT.png]: plot one drive_sil run (default RUN.png)
	@test -n "$(CSV)" || { echo "make plot: name the run: make plot CSV=RUN.csv [PNG=OUT.png]" >&2; exit 2; }
	@$(SIL_PLOT_BIN) "$(CSV)" $(if $(PNG),-o "$(PNG)")

# ---- make sil ------------------------------------------------------------
# Every tools/scenarios/*.ini through drive_sil into $(SIL_DIR)/<stem>.csv
# (and <stem>.resolved.json), its plot <stem>.png, the realistic ones
# (real_*) again over SIL_SEEDS into seeds/<stem>.jsonl (drive_sil --batch
# summaries), and report.md with its figures (sil-report).
# Incremental: a run is redone when its scenario or drive_sil's code changed, a
# plot when its CSV or sil_plot did, the report when any of
# them did (and its figures only for the runs that changed). One CSV and
# one seeds file per rule, so the runs go in parallel; `make sil` without
# -j runs its sub-make with -j$(SIL_JOBS). Plots of changed runs are drawn
# together by one sil-plot with SIL_JOBS processes (one
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
# its link options. The runs depend on a stamp of their checksum, which
# changes only with their contents (objects are reproducible: Makefile).
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

sil: $(DRIVEKIT) ## every tools/scenarios/*.ini in SIL: CSV, plot, seeds and report.md into build/sil/ (only what changed)
	@$(MAKE) --no-print-directory VARIANT=host $(if $(filter -j%,$(MAKEFLAGS)),,-j$(SIL_JOBS)) sil-update

sil-update: $(SIL_REPORT) ## (inside `make sil`) bring build/sil/ up to date; needs VARIANT=host and the venv

$(SIL_PROG_STAMP): $(SIL_PROG)
	@mkdir -p $(@D)
	@sum="$$(cat $(SIL_PROG_INPUTS) | sha256sum) $(PROG_LDOPT) $(PROG_LDLIBS)"; \
	 echo "$$sum" | cmp -s - $@ || echo "$$sum" > $@

$(SIL_DIR)/%.csv: tools/scenarios/%.ini $(SIL_PROG_STAMP)
	@mkdir -p $(@D)
	@$(SIL_PROG) --scenario $< --out $@ || [ $$? -eq 3 ]

$(SIL_DIR)/%.png: $(SIL_DIR)/%.csv tools/drivekit/drivekit/sil_plot.py
	@echo $< >> $(SIL_PLOT_QUEUE)

# The queue's CSVs that still have a scenario (an interrupted run may have left others).
sil-plots-update: $(SIL_PNGS) ## (inside `make sil`) draw the queued plots of changed runs in one process pool
	@rm -f $(SIL_PLOT_QUEUE) $(if $(filter $(SIL_CSVS),$(file < $(SIL_PLOT_QUEUE))),; \
	    $(SIL_PLOT_BIN) --quiet --jobs $(SIL_JOBS) $(sort $(filter $(SIL_CSVS),$(file < $(SIL_PLOT_QUEUE)))) && \
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
$(SIL_REPORT): $(SIL_CSVS) $(SIL_SEED_RUNS) $(SIL_LIST_STAMP) tools/drivekit/drivekit/sil_report.py \
               tools/drivekit/drivekit/metrics.py | sil-plots-update
	@$(VENV)/bin/sil-report --dir $(SIL_DIR) --jobs $(SIL_JOBS) || \
	 { touch -d @0 $@ 2> /dev/null; exit 1; }

sil-report: ## rewrite build/sil/report.md from the runs there (system python3: tables only)
	@$(call drivekit,sil_report) --dir $(BUILD)/sil

# ---- sensitivity maps (drivekit.sweep, drivekit.sweep_maps) --------------
#   make sweep            the default set into build/sweep/ (maps, report.md)
#   make test-sweep-net   the regression net of `make test`: a 5 x 5
#                         L x psi_f grid at 500 r/min, both methods;
#                         sweep_check asserts the proposed method is
#                         never faulted where the conventional one is
#                         not and never worse than it + 0.005 N m
#   make test-sweep-op-real  the realistic board at 100 and 371 r/min,
#                         six loads, both methods, same check
.PHONY: test-sweep-net test-sweep-op-real test-est-grid test-any-motor test-campaign test-zoo

SWEEP_DIR      := $(BUILD)/sweep
SWEEP_SCENARIO := tools/scenarios/prop_paper.ini
SWEEP_JOBS     ?= $(shell nproc)
SWEEP_ARGS      = --drive-sil $(DRIVE_SIL) --scenario $(SWEEP_SCENARIO) --jobs $(SWEEP_JOBS)
SWEEP_PY        = $(call drivekit,sweep) $(SWEEP_ARGS)

# The default set: mismatch planes with the plant exact
# elsewhere, and the operating plane with exact parameters. The operating
# point takes over from the paper's start-up (speed ramp, step 1 at 2 and
# 4 N m) at 0.6 s; the window is the paper's 0.8-0.95 s.
SWEEP_L_PSIF  := --grid controller.L_factor=0.5:2:9:log --grid controller.psif_factor=0.5:2:9:log
SWEEP_R_PSIF  := --grid controller.R_factor=0.5:4.5:9 --grid controller.psif_factor=0.5:2:9:log
SWEEP_OP      := --grid speed_rpm=100:2000:8 --grid load_Nm=0.5:6:6 \
                 --set 'reference.speed_rpm=0:0, 0.2:{speed_rpm}~' \
                 --set 'load.torque_Nm=0:2, 0.35:4, 0.6:{load_Nm}' \
                 --set run.duration_s=0.95 --window 0.8:0.95
# A realistic board: ADC noise, 1 us dead time compensated as 0.9 us, 1000-line encoder.
SWEEP_REAL    := --set plant.adc_noise_A=0.02 --set plant.deadtime_s=1e-6 \
                 --set controller.deadtime_s=0.9e-6 --set plant.encoder_lines=1000
SWEEP_SETS    := L_psif R_psif op

sweep: $(DRIVEKIT) $(DRIVE_SIL) ## sensitivity maps of both methods into build/sweep/ (PNGs, report.md)
	@set -e; for s in $(SWEEP_SETS); do \
	    case $$s in L_psif) g="$(SWEEP_L_PSIF)";; R_psif) g="$(SWEEP_R_PSIF)";; op) g="$(SWEEP_OP)";; esac; \
	    echo "sweep $$s (ideal sensors)"; \
	    eval "$(VENV)/bin/sil-sweep $(SWEEP_ARGS) $$g --out $(SWEEP_DIR)/$${s}_ideal"; \
	    echo "sweep $$s (realistic board)"; \
	    eval "$(VENV)/bin/sil-sweep $(SWEEP_ARGS) $$g $(SWEEP_REAL) --out $(SWEEP_DIR)/$${s}_real"; \
	done
	@$(VENV)/bin/sweep-maps --dir $(SWEEP_DIR)

# Regression net: fresh every time (no resume across builds), system python3.
SWEEP_NET_DIR := $(OUT)/sweep_net
EXTRA_TESTS += test-sweep-net
test-sweep-net: $(DRIVE_SIL) ## (part of make test) 5 x 5 L x psi_f net: proposed never worse
	@rm -rf $(SWEEP_NET_DIR)
	@$(SWEEP_PY) --quiet --jobs 2 --grid controller.L_factor=0.5:2:5 --grid controller.psif_factor=0.5:2:5 \
	    --log --out $(SWEEP_NET_DIR)
	@$(call suite,test-sweep-net) $(call drivekit,sweep_check) $(SWEEP_NET_DIR)

# Regression net: the realistic board at the low speeds of the
# operating map (SWEEP_OP's 100 and 371 r/min, its six loads, both
# methods), where the proposed method learned the inverter error left as
# flux (control/holds_design.md sec. 2).
SWEEP_LOW_DIR := $(OUT)/sweep_op_real_low
EXTRA_TESTS += test-sweep-op-real
test-sweep-op-real: $(DRIVE_SIL) ## (part of make test) realistic board at 100 and 371 r/min, six loads
	@rm -rf $(SWEEP_LOW_DIR)
	@$(SWEEP_PY) --quiet --jobs 2 --grid speed_rpm=100:371.4285714:2 --grid load_Nm=0.5:6:6 \
	    --set 'reference.speed_rpm=0:0, 0.2:{speed_rpm}~' --set 'load.torque_Nm=0:2, 0.35:4, 0.6:{load_Nm}' \
	    --set run.duration_s=0.95 --window 0.8:0.95 $(SWEEP_REAL) --out $(SWEEP_LOW_DIR)
	@$(call suite,test-sweep-op-real) $(call drivekit,sweep_check) $(SWEEP_LOW_DIR)

# The campaign's rule (drivekit.campaign_check): every pair in
# tests/campaign/ (both methods, the windows the files name); the pairs in
# tests/campaign/known_failures.txt are reported but do not fail (each
# line says why it still breaks the rule).
EXTRA_TESTS += test-campaign
test-campaign: $(DRIVE_SIL) ## (part of make test) the campaign's pairs keep the rule, known failures aside
	@$(call suite,test-campaign) $(call drivekit,campaign_check) tests/campaign --drive-sil $(DRIVE_SIL) \
	    --known tests/campaign/known_failures.txt

# The other motors' campaign (drivekit.rule_check): every pair in
# tests/campaign/any-motor/ (copies of ../shared/campaign/any-motor/, with
# the defaults the files leave unset) keeps the rule; no known failures.
EXTRA_TESTS += test-any-motor
test-any-motor: $(DRIVE_SIL) ## (part of make test) the any-motor campaign's pairs keep the rule
	@$(call suite,test-any-motor) $(call drivekit,rule_check) --drive-sil $(DRIVE_SIL) tests/campaign/any-motor

# The real motors and the advantage (drivekit.zoo_check): every motor of
# tests/campaign/zoo/ (copies of ../shared/campaign/zoo/) commissioned
# within its tolerances, its b_* files run with what the commissioning
# wrote and its c_* files as written, both methods (the conventional one
# within 3 % of T_rated, the proposed one within 1 % and the rule), and
# tests/campaign/advantage/'s pairs (proposed <= 0.5 x conventional); the
# checks in tests/campaign/zoo/known_failures.txt are reported, not counted.
EXTRA_TESTS += test-zoo
test-zoo: $(DRIVE_SIL) ## (part of make test) commission the zoo's motors, run their files with both methods, the advantage pairs
	@$(call suite,test-zoo) $(call drivekit,zoo_check) --drive-sil $(DRIVE_SIL) --jobs 2 \
	    --known tests/campaign/zoo/known_failures.txt

# The estimation's acceptance grids (drivekit.est_grid): dead time in the
# plant against the told one (psi_f^ within 2 % or held), a wrong told
# encoder offset (L^ within 5 % or held with the angle warning), both
# methods and the rule at every point; 2 drive_sil at a time.
EXTRA_TESTS += test-est-grid
test-est-grid: $(DRIVE_SIL) ## (part of make test) the estimation's dead-time and encoder-offset grids
	@$(call suite,test-est-grid) $(call drivekit,est_grid) --drive-sil $(DRIVE_SIL) --jobs 2 \
	    --known tests/est_grid/known_failures.txt

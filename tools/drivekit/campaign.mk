# tools/drivekit/campaign.mk - drive-campaign (tools/drivekit/): a Monte
# Carlo campaign of both methods over a motor file's tolerances.
#   make campaign MOTOR=F [DRAWS=N] [SEED=S] [OUT=DIR] [SCHEDULER=...] [JOBS=N] [FRESH=1]
#                         into OUT (default build/campaign/<motor file's stem>):
#                         results.parquet, report.md, worst/*.ini
#   make campaign-keys    rewrite tools/drivekit/CAMPAIGN_KEYS.md
#   make bench-campaign   draws per second per core (part of make bench)
# Unset, DRAWS (500), SEED (1), SCHEDULER (local) and JOBS (the cores) are
# drive-campaign's defaults. The Makefile keeps a command-line OUT= for the
# campaign (CAMPAIGN_OUT): the build's own OUT stays build/<variant>.
.PHONY: campaign campaign-keys bench-campaign

DRIVE_CAMPAIGN := $(VENV)/bin/drive-campaign
CAMPAIGN_DIR    = $(or $(CAMPAIGN_OUT),$(BUILD)/campaign/$(basename $(notdir $(MOTOR))))

# drive-campaign is one of drivekit's console scripts (module.mk installs it).
$(DRIVE_CAMPAIGN): $(DRIVEKIT)

# Asked for without a motor: said before anything is built.
ifneq ($(filter campaign,$(MAKECMDGOALS)),)
ifeq ($(strip $(MOTOR)),)
$(error make campaign: name the motor file: make campaign MOTOR=F [DRAWS=N] [SEED=S] [OUT=DIR] [SCHEDULER=local|dask-local|tcp://HOST:PORT] [JOBS=N] [FRESH=1])
endif
endif

campaign: $(DRIVE_CAMPAIGN) $(DRIVE_SIL) ## MOTOR=F [DRAWS=N SEED=S OUT=DIR SCHEDULER=local|dask-local|tcp://H:P]: Monte Carlo campaign of both methods
	@$(DRIVE_CAMPAIGN) '$(MOTOR)' --out '$(CAMPAIGN_DIR)' $(if $(DRAWS),--draws '$(DRAWS)') \
	    $(if $(SEED),--seed '$(SEED)') $(if $(SCHEDULER),--scheduler '$(SCHEDULER)') $(if $(JOBS),--jobs '$(JOBS)') \
	    --drive-sil $(DRIVE_SIL) $(if $(FRESH),--fresh)

campaign-keys: $(DRIVE_CAMPAIGN) ## rewrite tools/drivekit/CAMPAIGN_KEYS.md from the key table (drive-campaign --list-keys --markdown)
	$(DRIVE_CAMPAIGN) --list-keys --markdown > tools/drivekit/CAMPAIGN_KEYS.md

# The Python tools' tests (tests/test_campaign.py among them) run the installed drive-campaign.
test-tools: $(DRIVE_CAMPAIGN)

# 200 draws of the paper's motor (both methods each, the default tolerances), one drive_sil at a
# time: draws per second of one core, and 10^6 draws in core-hours.
BENCH_CAMPAIGN_DIR := $(OUT)/campaign_bench
bench-campaign: $(DRIVE_CAMPAIGN) $(DRIVE_SIL) ## draws per second per core of drive-campaign (part of bench)
	@rm -rf $(BENCH_CAMPAIGN_DIR)
	@$(DRIVE_CAMPAIGN) tools/scenarios/prop_paper.ini --out $(BENCH_CAMPAIGN_DIR) --draws 200 --jobs 1 --quiet \
	    --drive-sil $(DRIVE_SIL) | sed -n 's/^campaign: ran .*: \([0-9.]*\) draws\/s per core$$/\1/p' | \
	    awk '{ printf "bench campaign: %.1f draws/s per core (CPU time; both methods, prop_paper.ini, the default " \
	        "tolerances); 10^6 draws: %.1f core-hours\n", $$1, 1e6 / $$1 / 3600 }'

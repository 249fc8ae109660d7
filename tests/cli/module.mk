# tests/cli/module.mk - tests that run the built programs and the
# Makefile's helpers through their command lines (part of `make test`).
.PHONY: test-drive-sil-cli test-commission test-ensure-pkgs test-board test-nv

# The CLI: exit status 2 and no CSV on bad input (runs the built binary).
EXTRA_TESTS += test-drive-sil-cli
test-drive-sil-cli: $(DRIVE_SIL) ## (part of make test) drive_sil's command line: exit statuses, no CSV on bad input
	@$(call suite,test-drive-sil-cli) tests/cli/test_drive_sil_cli.sh $(DRIVE_SIL)

# Commissioning on three motors, ideal and realistic board, and its refusals
# (runs the built binary; standard-library Python).
EXTRA_TESTS += test-commission
test-commission: $(DRIVE_SIL) ## (part of make test) drive_sil --commission on three motors, ideal and realistic; refusals
	@$(call suite,test-commission) python3 tests/cli/test_commission.py $(DRIVE_SIL) tools/scenarios

# make board MOTOR=...: the image's configuration against drive_sil's run of the same
# file and against what the compiled image holds (tests/board_values.c, linked
# from make board's objects without main.c as $(BOARD_OUT)/board_values).
EXTRA_TESTS += test-board
test-board: $(DRIVE_SIL) ## (part of make test) make board on a 48 V motor file: its JSON, drive_sil's run, the compiled image
	@$(call suite,test-board) python3 tests/cli/test_board.py $(DRIVE_SIL)

# drive_sil --nv FILE: the link's save round trip through drivetool (stop, set, save, quit, a new
# run reads it back), and sector images built by the test from nv_store.h's format, loaded, refused.
EXTRA_TESTS += test-nv
test-nv: $(DRIVE_SIL) $(DRIVETOOL) ## (part of make test) drive_sil --nv with drivetool save: saved, read back at the next run; a corrupted block refused (NV_INVALID)
	@$(call suite,test-nv) python3 tests/cli/test_nv.py $(DRIVE_SIL) $(DRIVETOOL)

$(BOARD_OUT)/board_values: tests/board_values.c $(BOARD_OBJS)
	@$(CC) -O2 $(CF_TEST) $(INC) -DDRIVE_CONFIG -I$(BOARD_OUT) -o $@ $< $(filter-out %/main.o,$(BOARD_OBJS)) -lm

# tools/make/ensure_pkgs.sh under -j: concurrent callers, one apt-get (fakes on PATH).
EXTRA_TESTS += test-ensure-pkgs
test-ensure-pkgs: ## (part of make test) tools/make/ensure_pkgs.sh under -j, against a fake apt-get
	@$(call suite,test-ensure-pkgs) tests/cli/test_ensure_pkgs.sh

# tools/sil: the SIL runner (a host harness of the application, above
# firmware/ and hal/sim/): scenario and profile parsing (libsilrun.a),
# sil_run() and the program $(OUT)/drive_sil. See hal/sim/README.md.

DRIVE_SIL := $(OUT)/drive_sil
HOST_PROGRAMS += $(DRIVE_SIL)

# sil.o is linked as an object, ahead of the libraries: it calls the app
# (libfirmware), which calls the HAL (libsim) - one pass of "firmware sim
# control" resolves that. Tests calling sil_run() do the same:
#   TEST_SRCS_test_x := tools/sil/sil.c   TEST_LIBS_test_x := silrun firmware sim control
# drive_sil --version: the source revision (sil_version.h), written into a
# generated source that is rewritten only when the revision changes: a new
# commit recompiles that one file and relinks drive_sil, nothing else.
SIL_VERSION_C := $(OUT)/gen/sil_version.c
$(SIL_VERSION_C): FORCE
	@mkdir -p $(@D)
	@rev=$$(git describe --always --dirty 2>/dev/null | tr -cd 'A-Za-z0-9._+-'); \
	 line="const char sil_revision[] = \"$${rev:-unknown}\";"; \
	 echo "$$line" | cmp -s - $@ || echo "$$line" > $@

DRIVE_SIL_INPUTS := $(call objs,tools/sil/drive_sil.c tools/sil/csv_writer.c tools/sil/sil.c tools/sil/link_sil.c $(SIL_VERSION_C)) \
                    $(LIB_silrun) $(LIB_firmware) $(LIB_sim) $(LIB_control)
$(DRIVE_SIL): $(DRIVE_SIL_INPUTS)
	@mkdir -p $(@D)
	$(CC) $(OPT) $(PROG_LDOPT) -o $@ $(filter %.o,$^) $(filter %.a,$^) $(PROG_LDLIBS)

# The documented key list, generated from the key table (tools/sil/scenario_keys.h);
# test-drive-sil-cli checks that the checked-in one is the table's.
.PHONY: scenario-keys
scenario-keys: $(DRIVE_SIL) ## rewrite tools/sil/SCENARIO_KEYS.md from the key table (drive_sil --list-keys --markdown)
	$(DRIVE_SIL) --list-keys --markdown > tools/sil/SCENARIO_KEYS.md

TEST_LIBS_test_scenario := silrun firmware sim control
TEST_LIBS_test_ini_edit := silrun
# The app's commissioning in SIL (sil_run_ctl with commission).
TEST_LIBS_test_sil_commission := silrun firmware sim control
TEST_SRCS_test_sil_commission := tools/sil/sil.c
TEST_LIBS_test_sil      := silrun firmware sim control
TEST_SRCS_test_sil      := tools/sil/sil.c
# The app's start-up sequence (calibrate, align, run) in SIL.
TEST_LIBS_test_sil_startup := silrun firmware sim control
TEST_SRCS_test_sil_startup := tools/sil/sil.c

# The CLI: exit status 2 and no CSV on bad input (runs the built binary).
.PHONY: test-drive-sil-cli
EXTRA_TESTS += test-drive-sil-cli
test-drive-sil-cli: $(DRIVE_SIL) ## (part of make test) drive_sil's command line: exit statuses, no CSV on bad input
	@$(call suite,test-drive-sil-cli) tools/test_drive_sil_cli.sh $(DRIVE_SIL)

# Commissioning on three motors, ideal and realistic board, and its refusals
# (runs the built binary; standard-library Python).
.PHONY: test-commission
EXTRA_TESTS += test-commission
test-commission: $(DRIVE_SIL) ## (part of make test) drive_sil --commission on three motors, ideal and realistic; refusals
	@$(call suite,test-commission) python3 tools/test_commission.py $(DRIVE_SIL) tools/scenarios

# Acceptance of the proposed method on the simulated board (scenario files
# of tools/scenarios/, and the controller alone on hal_sim).
TEST_LIBS_test_sil_proposed := silrun firmware sim control
TEST_SRCS_test_sil_proposed := tools/sil/sil.c
# Current and torque limits, estimation through transients, flux
# weakening; both methods on the scenarios prop_lim_*, prop_fw_*.
TEST_LIBS_test_sil_limits := silrun firmware sim control
TEST_SRCS_test_sil_limits := tools/sil/sil.c

# Fault injection ([faults]) against the app's protection.
TEST_LIBS_test_sil_faults := silrun firmware sim control
TEST_SRCS_test_sil_faults := tools/sil/sil.c
# The gates off: the diode bridge, the passive load, the readings in every state.
TEST_LIBS_test_sil_gates_off := silrun firmware sim control
TEST_SRCS_test_sil_gates_off := tools/sil/sil.c

# Step 1 on a real ADC: noise, offsets, inertia, the R^
# band, the refusal policy; both methods on the same scenarios.
TEST_LIBS_test_sil_identify := silrun firmware sim control
TEST_SRCS_test_sil_identify := tools/sil/sil.c
# Three motors told only their data (tools/scenarios/*_motor_*.ini).
TEST_LIBS_test_sil_motors := silrun firmware sim control
TEST_SRCS_test_sil_motors := tools/sil/sil.c

# The proposed method on a real inverter: inverter error, warming winding.
TEST_LIBS_test_sil_inverter := silrun firmware sim control
TEST_SRCS_test_sil_inverter := tools/sil/sil.c
# The CSV's number format (csv_num.c, in libsilrun) against printf.
TEST_LIBS_test_csv_num := silrun
# drive_sil's CSV writer thread: bytes as sil_csv_row(), write errors.
TEST_LIBS_test_csv_writer := silrun firmware sim control
TEST_SRCS_test_csv_writer := tools/sil/csv_writer.c tools/sil/sil.c

# app_init and cmd_init on pattern-filled memory (COFF zeroes nothing):
# main.c's sequence on the simulated board, bit-identical for every pattern.
TEST_LIBS_test_app_init_pattern := silrun firmware sim control

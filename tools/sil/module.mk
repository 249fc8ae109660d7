# tools/sil: the SIL runner (a host harness of the application, above
# firmware/ and hal/sim/): scenario and profile parsing (libsilrun.a),
# sil_run() and the program $(OUT)/drive_sil. See tools/sil/README.md.

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

DRIVE_SIL_INPUTS := $(call objs,tools/sil/drive_sil.c tools/sil/csv_writer.c tools/sil/sil.c tools/sil/link_sil.c \
                    tools/sil/board_config.c $(SIL_VERSION_C)) \
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
# drive_sil --nv FILE: the simulated board's parameter sector kept in FILE (nv_file.h).
TEST_LIBS_test_sil_nv := silrun firmware sim control
# The CSV's number format (csv_num.c, in libsilrun) against printf.
TEST_LIBS_test_csv_num := silrun
# drive_sil's CSV writer thread: bytes as sil_csv_row(), write errors.
TEST_LIBS_test_csv_writer := silrun firmware sim control
TEST_SRCS_test_csv_writer := tools/sil/csv_writer.c tools/sil/sil.c
# app_init and cmd_init on pattern-filled memory (COFF zeroes nothing):
# main.c's sequence on the simulated board, bit-identical for every pattern.
TEST_LIBS_test_app_init_pattern := silrun firmware sim control

# The SIL's acceptance tests, on sil_run():
#   test_sil             the runner itself
#   test_sil_commission  the app's commissioning (sil_run_ctl with commission)
#   test_sil_startup     the start-up sequence (calibrate, align, run)
#   test_sil_proposed    the proposed method (scenario files of tools/scenarios/,
#                        and the controller alone on hal_sim)
#   test_sil_limits      current and torque limits, estimation through
#                        transients, flux weakening (prop_lim_*, prop_fw_*)
#   test_sil_faults      fault injection ([faults]) against the protection
#   test_sil_gates_off   the gates off: the diode bridge, the passive load,
#                        the readings in every state
#   test_sil_identify    step 1 on a real ADC: noise, offsets, inertia, the R^
#                        band, the refusal policy; both methods
#   test_sil_motors      three motors told only their data (*_motor_*.ini)
#   test_sil_inverter    the proposed method on a real inverter: its error, a
#                        warming winding
$(call sil_tests,test_sil test_sil_commission test_sil_startup test_sil_proposed test_sil_limits \
    test_sil_faults test_sil_gates_off test_sil_identify test_sil_motors test_sil_inverter)

# firmware/ (its rooms: README.md, rooms.mk): the unit tests' wiring.
# Against the cmocka mock of the HAL (tests/mock_hal.c, tests/app_harness.h):
#   test_app         the app: ISR glue, state machine
#   test_cmd         the operator's command block
#   test_calib, test_align, test_protect, test_rsid_seq
#                    the start-up steps and protection, a runner each
#   test_link        the link's dispatcher, capture and stream (link_protocol.md)
#   test_startup     what runs before the drive: the flash CRC check, the start-up faults
#   test_commission  the commissioning's step machine on a small test-side motor
$(call mock_tests,test_app test_cmd test_calib test_align test_protect test_rsid_seq test_link test_startup \
    test_commission)

# Without the HAL: the values derived from the motor's data
# (params_design.md), the link's codec against the golden vectors, the
# encoder and wiring check (enc_check.h) on hand-made periods, the
# parameter store (nv_store.h).
TEST_LIBS_test_drive_params := firmware control
TEST_LIBS_test_link_codec := firmware control
TEST_LIBS_test_enc_check := firmware control
# The parameter store's blocks in a sector emulated as flash (nv_store.h),
# over the parameter set through a list of parameters (nv_params.h), and
# the link's table as that list (link_nv.h).
TEST_LIBS_test_nv_store := firmware control
TEST_LIBS_test_nv_params := firmware control
TEST_LIBS_test_link_nv := firmware control

# Closed-loop acceptance of the conventional DB-DTC on the simulated board,
# and the build levels there (test_sil_levels).
TEST_LIBS_test_sil_conventional := silrun firmware sim control
$(call sil_tests,test_sil_levels)

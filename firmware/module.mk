# firmware/ (its rooms: README.md, rooms.mk): the unit tests' wiring. The
# app (ISR glue, state machine) runs against the cmocka mock of the HAL.
TEST_LIBS_test_app := firmware control
TEST_SRCS_test_app := tests/mock_hal.c
# The values derived from the motor's data (params_design.md).
TEST_LIBS_test_drive_params := firmware control

# Closed-loop acceptance of the conventional DB-DTC on the simulated board.
TEST_LIBS_test_sil_conventional := silrun firmware sim control

# The operator's command block, against the same HAL mock.
TEST_LIBS_test_cmd := firmware control
TEST_SRCS_test_cmd := tests/mock_hal.c

# The start-up steps and protection, each with its own runner, against
# the same HAL mock (tests/app_harness.h).
TEST_LIBS_test_calib    := firmware control
TEST_SRCS_test_calib    := tests/mock_hal.c
TEST_LIBS_test_align    := firmware control
TEST_SRCS_test_align    := tests/mock_hal.c
TEST_LIBS_test_protect  := firmware control
TEST_SRCS_test_protect  := tests/mock_hal.c
TEST_LIBS_test_rsid_seq := firmware control
TEST_SRCS_test_rsid_seq := tests/mock_hal.c

# The link (link_protocol.md): codec against the golden vectors, the
# dispatcher, capture and stream against the HAL mock.
TEST_LIBS_test_link_codec := firmware control
TEST_LIBS_test_link := firmware control
TEST_SRCS_test_link := tests/mock_hal.c

# What runs before the drive: the flash CRC check and the start-up faults.
TEST_LIBS_test_startup := firmware control
TEST_SRCS_test_startup := tests/mock_hal.c

# The commissioning's step machine on a small test-side motor.
TEST_LIBS_test_commission := firmware control
TEST_SRCS_test_commission := tests/mock_hal.c

# The encoder and wiring check (enc_check.h) on hand-made periods, and the
# build levels on the simulated board (tests/test_sil_levels.c).
TEST_LIBS_test_enc_check := firmware control
TEST_LIBS_test_sil_levels := silrun firmware sim control
TEST_SRCS_test_sil_levels := tools/sil/sil.c

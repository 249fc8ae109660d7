# firmware/: the app (ISR glue, state machine). Its unit test runs against
# the cmocka mock of the HAL.
TEST_LIBS_test_app := firmware control
TEST_SRCS_test_app := tests/mock_hal.c

# Closed-loop acceptance of the conventional DB-DTC on the simulated board.
TEST_LIBS_test_sil_conventional := firmware sim control

# The operator's command block, against the same HAL mock.
TEST_LIBS_test_cmd := firmware control
TEST_SRCS_test_cmd := tests/mock_hal.c

# hal/f28335/module.mk - host wiring of the F28335 HAL and its register fake.
# hal/f28335/*.c and tests/c2000_fake/*.c are archived into libf28335.a by
# the top-level Makefile; the target build is firmware/f28335/target.mk.
TEST_LIBS_test_hal_f28335 := f28335 control
TEST_LIBS_test_c2000_fake := f28335
# The application on this HAL over the register fake (firmware -> hal/f28335).
TEST_LIBS_test_app_f28335 := firmware f28335 control
# The parameter store's sector through TI's flash API (its fake), and nv_store over it.
TEST_LIBS_test_nv_f28335 := firmware f28335 control

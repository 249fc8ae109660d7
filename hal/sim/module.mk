# hal/sim: the simulated board (libsim.a, archived by the top Makefile):
# plant, inverter, sensors and hal_sim. The SIL runner that drives the
# firmware on it lives in tools/sil/. See hal/sim/README.md.

# The plant and inverter tests take the Table I motor from the SIL's
# parameter-set defaults (tests/table1.h).
TEST_LIBS_test_plant    := silrun firmware sim control
TEST_LIBS_test_inverter := silrun firmware sim control
TEST_LIBS_test_sensors  := sim

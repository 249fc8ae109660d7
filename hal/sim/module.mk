# hal/sim: the simulated board (libsim.a, archived by the top Makefile):
# plant, inverter, sensors and hal_sim. The SIL runner that drives the
# firmware on it lives in tools/sil/. See hal/sim/README.md.

TEST_LIBS_test_plant    := sim
TEST_LIBS_test_inverter := sim
TEST_LIBS_test_sensors  := sim

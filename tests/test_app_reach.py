#!/usr/bin/env python3
"""tests/test_app_reach.py - tools/check/app_reach.sh, the tests' surface
gate of `make check`, on throw-away trees: a test reading or writing an
app_t's controller member (`app.ctrl.mon`, `&app.ctrl`, any variable's
name) fails it, naming file and line, and so does a member access through
a reader's result; the probe (tests/app_probe.h) may; a test through
app_ctrl() and ctrl.h's readers, or a configuration's `cfg.ctrl`, passes."""
import unittest

from gate_tree import GateCase

CLEAN = ("static void t(void)\n{\n"
         "    assert_int_equal(ctrl_status(app_ctrl(&app)), CTRL_CFG_OK);\n"
         "    assert_int_equal(est_output(ctrl_est(app_ctrl(&app)))->phase, EST_OFF);\n"
         "    assert_float_equal(app_monitor(&app)->id_A, 0.5, 1e-4);\n"
         "    cfg.ctrl.R_Ohm = 3.0f;\n    app.cfg.ctrl.L_H = 0.011f;\n"
         "    ctrl_set_ref(probe_ctrl_rw(&app), &r);\n}\n")


class AppReach(GateCase):
    SCRIPT = "app_reach.sh"
    DIRS = ("tests/fuzz",)

    def setUp(self):
        super().setUp()
        self.write("tests/app_probe.h", "static inline ctrl_mon_t *probe_monitor_rw(app_t *a) { return &a->ctrl.mon; }\n")
        self.write("tests/test_app.c", CLEAN)

    def test_public_surface_and_the_probe_pass(self):
        rc, out = self.run_gate()
        self.assertEqual(rc, 0, out)

    def test_member_read_fails(self):
        self.write("tests/test_app.c", CLEAN + "static void u(void)\n{\n    x = app.ctrl.mon.id_A;\n}\n")
        self.assert_gate_fails("FAIL tests/test_app.c: reaches into the app's controller", "12:    x = app.ctrl.mon.id_A;")

    def test_handle_and_other_names_fail(self):
        self.write("tests/test_link.c", "ctrl_set_ref(&app.ctrl, &r);\n")
        self.write("tests/fuzz/fuzz_link.c", "g_app.ctrl.mon.iq_A = 1.0f;\nin_place->ctrl.status = 0u;\n")
        self.assert_gate_fails("FAIL tests/test_link.c: reaches into the app's controller",
                               "FAIL tests/fuzz/fuzz_link.c: reaches into the app's controller",
                               "1:g_app.ctrl.mon.iq_A", "2:in_place->ctrl.status")

    def test_access_through_a_reader_fails(self):
        self.write("tests/test_cmd.c", "x = app_ctrl(&app)->mon.id_A;\ny = ctrl_est(app_ctrl(&app))->smo.R_Ohm;\n"
                   "probe_ctrl_rw(&app)->status = 0u;\n")
        self.assert_gate_fails("FAIL tests/test_cmd.c: reaches into the controller through a reader's result",
                               "1:x = app_ctrl", "2:y = ctrl_est", "3:probe_ctrl_rw")


if __name__ == "__main__":
    unittest.main()

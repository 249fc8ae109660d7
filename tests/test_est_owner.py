#!/usr/bin/env python3
"""tests/test_est_owner.py - tools/check/est_owner.sh, the estimation's
owner gate of `make check`, on throw-away trees: a call of a block's
function from outside the estimation fails it, a name with digits
(est_gate_accel_floor_rad_s2) included, naming file and line; a member
access through an est_t fails it; a tree that only calls est.h passes."""
import unittest

from gate_tree import GateCase


class EstOwner(GateCase):
    SCRIPT = "est_owner.sh"
    DIRS = ("control/est", "control/ctrl")

    def setUp(self):
        super().setUp()
        self.write("control/est/est.c", "void f(void) { est_gate_accel_floor_rad_s2(1u, 3u, 500.0f); }\n")
        self.write("control/est/est_gate.c", "float est_gate_accel_floor_rad_s2(void) { return 0.0f; }\n")

    def test_clean_tree_passes(self):
        self.write("control/ctrl/ctrl.c", "void g(est_t *e) { est_step(e, 0); est_cfg_defaults(0, 0, 0, 0.0f, 0.0f); "
                   "smo_cfg_defaults(0, 0.0f, 0.0f, 0.0f, 0.0f); }\n")
        rc, out = self.run_gate()
        self.assertEqual(rc, 0, out)

    def test_call_with_digits_in_the_name_fails(self):
        self.write("control/ctrl/ctrl.c", "void g(void)\n{\n    x = est_gate_accel_floor_rad_s2(4u, 3u, 500.0f);\n}\n")
        self.assert_gate_fails("FAIL control/ctrl/ctrl.c: calls an estimation block directly",
                               "3:    x = est_gate_accel_floor_rad_s2(")

    def test_member_access_fails(self):
        self.write("control/ctrl/ctrl.c", "float h(const ctrl_t *c) { return c->est.smo.L_H; }\n")
        self.assert_gate_fails("FAIL control/ctrl/ctrl.c: touches the estimation's members")


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/env python3
"""tests/test_est_owner.py - tools/check/est_owner.sh, the estimation's
owner gate of `make check`, on throw-away trees: a call of a block's
function from outside the estimation fails it, a name with digits
(est_gate_accel_floor_rad_s2) included, naming file and line; a member
access through an est_t fails it; a tree that only calls est.h passes."""
import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "tools", "check", "est_owner.sh")


class EstOwner(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.root = self._tmp.name
        os.makedirs(os.path.join(self.root, "tools", "check"))
        os.makedirs(os.path.join(self.root, "control", "est"))
        os.makedirs(os.path.join(self.root, "control", "ctrl"))
        shutil.copy(SCRIPT, os.path.join(self.root, "tools", "check", "est_owner.sh"))
        self.write("control/est/est.c", "void f(void) { est_gate_accel_floor_rad_s2(1u, 3u, 500.0f); }\n")
        self.write("control/est/est_gate.c", "float est_gate_accel_floor_rad_s2(void) { return 0.0f; }\n")

    def tearDown(self):
        self._tmp.cleanup()

    def write(self, rel, text):
        with open(os.path.join(self.root, rel), "w", encoding="utf-8") as f:
            f.write(text)

    def run_gate(self):
        p = subprocess.run(["bash", os.path.join(self.root, "tools", "check", "est_owner.sh")],
                           capture_output=True, text=True)
        return p.returncode, p.stdout

    def test_clean_tree_passes(self):
        self.write("control/ctrl/ctrl.c", "void g(est_t *e) { est_step(e, 0); est_cfg_defaults(0, 0, 0, 0.0f, 0.0f); "
                   "smo_cfg_defaults(0, 0.0f, 0.0f, 0.0f, 0.0f); }\n")
        rc, out = self.run_gate()
        self.assertEqual(rc, 0, out)

    def test_call_with_digits_in_the_name_fails(self):
        self.write("control/ctrl/ctrl.c", "void g(void)\n{\n    x = est_gate_accel_floor_rad_s2(4u, 3u, 500.0f);\n}\n")
        rc, out = self.run_gate()
        self.assertEqual(rc, 1, out)
        self.assertIn("FAIL control/ctrl/ctrl.c: calls an estimation block directly", out)
        self.assertIn("3:    x = est_gate_accel_floor_rad_s2(", out)

    def test_member_access_fails(self):
        self.write("control/ctrl/ctrl.c", "float h(const ctrl_t *c) { return c->est.smo.L_H; }\n")
        rc, out = self.run_gate()
        self.assertEqual(rc, 1, out)
        self.assertIn("FAIL control/ctrl/ctrl.c: touches the estimation's members", out)


if __name__ == "__main__":
    unittest.main()

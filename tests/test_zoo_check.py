#!/usr/bin/env python3
"""tests/test_zoo_check.py - drivekit.zoo_check's own parts on files and
summaries built by hand: a b file takes every key of the commissioned
[controller] and [identify] with its own method, reference, load and run;
the exact run tells each value as the file gives it (absolute or factor);
the proposed method's verdict (1 % of T_rated, or within 0.5 % of the
conventional method told the exact values where that is above 1 %, and
the rule). Standard library only (unittest); `make test-tools`.
"""
import contextlib
import io
import os
import sys
import tempfile
import unittest

DRIVEKIT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools", "drivekit")
sys.path.insert(0, DRIVEKIT)
from drivekit import zoo_check  # noqa: E402

B_FILE = """; win steady = 3.2:4.0
; a comment naming [controller] must not start a section
[plant]
R_ohm = 0.61
psif_Wb = 0.15

[controller]
R_ohm = 0.5
psif_Wb = 0.14
method = proposed

[reference]
speed_rpm = 0:0, 0.3:3000~

[load]
torque_Nm = 0:1.2
"""
OUT = {"controller": {"R_ohm": "0.6101", "psif_Wb": "0.1479", "device_drop_V": "2.1", "method": "proposed"},
       "identify": {"mode": "trusted"}}


def summ(te, fault="NONE"):
    return {"te_err_Nm": te, "fault_name": fault, "final_state_name": "RUN" if fault == "NONE" else "FAULT"}


class WithSections(unittest.TestCase):
    def write(self, method):
        with tempfile.TemporaryDirectory() as d:
            src, dst = os.path.join(d, "b.ini"), os.path.join(d, "run.ini")
            with open(src, "w") as f:
                f.write(B_FILE)
            zoo_check.with_sections(src, OUT, method, dst)
            return zoo_check.read_ini(dst)[1]

    def test_takes_every_commissioned_key_and_keeps_the_method_and_run(self):
        v = self.write("conventional")
        self.assertEqual(v["controller"], {"R_ohm": "0.6101", "psif_Wb": "0.1479", "device_drop_V": "2.1",
                                           "method": "conventional"})
        self.assertEqual(v["identify"], {"mode": "trusted"})
        self.assertEqual(v["reference"], {"speed_rpm": "0:0, 0.3:3000~"})
        self.assertEqual(v["load"], {"torque_Nm": "0:1.2"})
        self.assertEqual(v["plant"]["R_ohm"], "0.61")

    def test_exact_run_tells_the_plant_as_the_file_spells_it(self):
        values = {"plant": {"R_ohm": "0.61", "L_H": "0.0042", "psif_Wb": "0.15", "J_kgm2": "5e-4",
                            "deadtime_s": "1e-6", "device_drop_V": "1.5"},
                  "controller": {"R_ohm": "0.5", "L_factor": "0.7"}}
        s = zoo_check.exact_sets(values)
        self.assertIn("controller.R_ohm=0.61", s)           # absolute in the file: absolute
        self.assertIn("controller.L_factor=1", s)           # a factor in the file: factor 1
        self.assertIn("controller.psif_factor=1", s)
        self.assertIn("controller.deadtime_s=1e-6", s)
        self.assertIn("controller.device_drop_V=1.5", s)


class ProposedVerdict(unittest.TestCase):
    def verdicts(self, prop, conv, exact):
        v = zoo_check.Verdicts(set())
        with contextlib.redirect_stdout(io.StringIO()):
            zoo_check.judge_prop(v, "b_x", prop, conv, exact, 1.0)
        return dict(v.rows)

    def test_within_one_percent_passes(self):
        r = self.verdicts(summ(0.009), summ(0.02), summ(0.005))
        self.assertEqual(r["b_x prop"], "ok  ")
        self.assertEqual(r["b_x rule"], "ok  ")

    def test_noise_floor_allows_half_a_percent_above_it(self):
        self.assertEqual(self.verdicts(summ(0.016), summ(0.03), summ(0.012))["b_x prop"], "ok  ")
        self.assertEqual(self.verdicts(summ(0.018), summ(0.03), summ(0.012))["b_x prop"], "FAIL")
        # no floor above 1 %: the 1 % holds
        self.assertEqual(self.verdicts(summ(0.012), summ(0.03), summ(0.008))["b_x prop"], "FAIL")

    def test_fault_and_rule(self):
        self.assertEqual(self.verdicts(summ(0.0, "OVERCURRENT"), summ(0.01), summ(0.005))["b_x prop"], "FAIL")
        r = self.verdicts(summ(0.009), summ(0.003), summ(0.002))
        self.assertEqual(r["b_x rule"], "FAIL")             # 0.009 > 0.003 + 0.005


if __name__ == "__main__":
    unittest.main()

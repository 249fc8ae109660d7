#!/usr/bin/env python3
"""tests/test_motor_timeline.py - drivekit.motor_timeline: the generated
tools/scenarios/*_motor_*_timeline.ini are up to date (--check), their
speed and loads are the paper's timeline in per unit of each motor's
ratings (computed here from the ratings by hand: T_rated = 1.5 p psi_f
i_rated), and --check fails on a file edited by hand."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = ["-m", "drivekit.motor_timeline"]
ENV = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "tools", "drivekit"), PYTHONDONTWRITEBYTECODE="1")
SCEN = os.path.join(ROOT, "tools", "scenarios")

# motor: (n_rated [r/min], T_rated [N m]) from the ratings of its 3 s scenario
RATED = {
    "paper": (2000.0, 6.0),                          # Table I: 6 N m, 2000 r/min
    "small": (3000.0, 1.5 * 4 * 0.008 * 6.25),       # 0.3 N m
    "large": (1500.0, 1.5 * 4 * 0.35 * 9.5238),      # 20.0 N m
}


def value_of(path, section, key):
    sec = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.split(";")[0].strip()
            if line.startswith("["):
                sec = line.strip("[]")
            elif sec == section and line.startswith(key + " ="):
                return line.split("=", 1)[1].strip()
    raise KeyError(key)


def points(profile):
    return [tuple(float(x) for x in p.strip().rstrip("~").split(":")) for p in profile.split(",")]


class MotorTimeline(unittest.TestCase):
    def test_files_up_to_date(self):
        p = subprocess.run([sys.executable, *SCRIPT, "--check"], capture_output=True, text=True, env=ENV, cwd=ROOT)
        self.assertEqual(p.returncode, 0, p.stderr)

    def test_per_unit_of_the_ratings(self):
        for motor, (n_rated, t_rated) in RATED.items():
            for method in ("conv", "prop"):
                path = os.path.join(SCEN, f"{method}_motor_{motor}_timeline.ini")
                speed = points(value_of(path, "reference", "speed_rpm"))
                self.assertEqual(speed[0], (0.0, 0.0))
                self.assertAlmostEqual(speed[-1][0], 0.2)
                self.assertAlmostEqual(speed[-1][1] / n_rated, 0.25, places=5)
                load = points(value_of(path, "load", "torque_Nm"))
                self.assertEqual([t for t, _ in load], [0.0, 0.35, 0.95, 1.05])
                for (_, v), pu in zip(load, (1 / 3, 2 / 3, 1.0, 2 / 3)):
                    self.assertAlmostEqual(v / t_rated, pu, places=4)

    def test_check_fails_on_an_edited_file(self):
        with tempfile.TemporaryDirectory() as d:
            for name in os.listdir(SCEN):
                if "_motor_" in name:
                    shutil.copy(os.path.join(SCEN, name), d)
            path = os.path.join(d, "prop_motor_small_timeline.ini")
            with open(path, "a", encoding="utf-8") as f:
                f.write("; edited\n")
            p = subprocess.run([sys.executable, *SCRIPT, "--check", "--dir", d], capture_output=True, text=True,
                               env=ENV)
            self.assertEqual(p.returncode, 1)
            self.assertIn("prop_motor_small_timeline.ini", p.stderr)
            subprocess.run([sys.executable, *SCRIPT, "--dir", d], check=True, env=ENV)
            p = subprocess.run([sys.executable, *SCRIPT, "--check", "--dir", d], capture_output=True, text=True,
                               env=ENV)
            self.assertEqual(p.returncode, 0, p.stderr)


if __name__ == "__main__":
    unittest.main()

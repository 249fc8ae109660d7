#!/usr/bin/env python3
"""tests/test_sweep.py - drive_sil's summary mode and drivekit.sweep against
the independent path: drive_sil's CSV read by drivekit.metrics. Standard
library only (unittest); `make test-tools` runs it with DRIVE_SIL set to
the built runner (default build/host/drive_sil; skipped when absent).

The summary is computed in C while the run goes, metrics.py from the
CSV's 9-digit numbers, so the figures agree to the CSV's rounding: the
tolerances below are a few units of the 9th digit of each figure's inputs
(torque ~10 N m, flux ~0.3 Wb, speed ~2000 r/min, estimates ~1 x truth).
"""
import contextlib
import csv
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRIVEKIT = os.path.join(ROOT, "tools", "drivekit")
sys.path.insert(0, DRIVEKIT)
from drivekit import metrics, sweep, sweep_check  # noqa: E402
ENV = dict(os.environ, PYTHONPATH=DRIVEKIT)

DRIVE_SIL = os.path.abspath(os.environ.get("DRIVE_SIL", os.path.join(ROOT, "build", "host", "drive_sil")))
SCENARIO = os.path.join(ROOT, "tools", "scenarios", "prop_paper.ini")
TRUTH = (3.0, 0.011, 0.24)          # prop_paper.ini's plant
APP_STATE_RUN = 5                   # firmware/app/app.h
TOL = {"te_err_Nm": 1e-7, "te_ripple_Nm": 1e-7, "psi_err_Wb": 1e-9, "psi_err_pct": 1e-6,
       "speed_err_rpm": 1e-5, "speed_err_max_rpm": 1e-5, "id_A": 1e-7, "iq_A": 1e-7,
       "R_err_pct": 1e-5, "L_err_pct": 1e-5, "psif_err_pct": 1e-5}


def have_drive_sil():
    return os.path.isfile(DRIVE_SIL) and os.access(DRIVE_SIL, os.X_OK)


def run_sweep(*args):
    """sweep.py's main() with its stderr captured: (exit status, stderr text)."""
    r = subprocess.run([sys.executable, "-m", "drivekit.sweep", "--drive-sil", DRIVE_SIL,
                        "--quiet", *args], capture_output=True, text=True, cwd=ROOT, env=ENV)
    return r.returncode, r.stderr


def by_hand(tmp, sets, window=None):
    """drive_sil --out CSV, then metrics.py on it (its command line, JSON out)."""
    path = os.path.join(tmp, "hand.csv")
    cmd = [DRIVE_SIL, "--scenario", SCENARIO, "--out", path]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    mcmd = [sys.executable, "-m", "drivekit.metrics", path, "--json",
            "--truth", ":".join(repr(x) for x in TRUTH)]
    if window:
        mcmd += ["--window", window]
    out = subprocess.run(mcmd, check=True, capture_output=True, text=True, env=ENV).stdout
    return json.loads(out), metrics.load_csv(path)


@unittest.skipUnless(have_drive_sil(), f"{DRIVE_SIL} not built")
class SummaryMode(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def assert_figures_equal(self, summary, hand):
        for k, tol in TOL.items():
            a, b = summary[k], hand.get(k)
            if b is None:
                self.assertIsNone(a, k)
            else:
                self.assertAlmostEqual(a, b, delta=tol, msg=k)

    def test_summary_file_equals_metrics_of_the_csv_of_the_same_run(self):
        js = os.path.join(self.tmp, "s.json")
        csv_path = os.path.join(self.tmp, "s.csv")
        sets = ["controller.L_factor=0.66", "controller.psif_factor=1.5"]
        cmd = [DRIVE_SIL, "--scenario", SCENARIO, "--out", csv_path, "--summary", js]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, capture_output=True)
        with open(js) as f:
            summary = json.load(f)
        hand = metrics.compute(csv_path, truth=TRUTH)
        self.assert_figures_equal(summary, hand)
        col = metrics.load_csv(csv_path)
        self.assertEqual(summary["window_rows"], sum(1 for t in col["t_s"] if 0.8 <= t < 0.95))
        self.assertEqual(summary["final_state"], hand["final_state"])
        self.assertEqual(summary["max_abs_i_A"] > 0, True)
        self.assertAlmostEqual(summary["controller.L_H"], 0.66 * TRUTH[1], delta=1e-12)

    def test_summary_alone_writes_no_csv_and_the_window_is_given(self):
        # a short averaged torque-mode run: the window option and the NaN speed reference (null)
        sets = ["controller.mode=torque", "reference.torque_Nm=0:1, 0.05:3", "run.duration_s=0.1",
                "plant.model=averaged"]
        cmd = [DRIVE_SIL, "--scenario", SCENARIO, "--summary", "-", "--window", "0.06:0.09"]
        for s in sets:
            cmd += ["--set", s]
        r = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=self.tmp)
        summary = json.loads(r.stdout)
        self.assertEqual(os.listdir(self.tmp), [])
        hand, _ = by_hand(self.tmp, sets, window="0.06:0.09")
        self.assertIsNone(summary["speed_err_rpm"])
        self.assert_figures_equal(summary, hand)

    def test_fallback_named_from_the_csv_columns(self):
        # step 1 forced to refuse (a band that holds no R^ it could measure): the
        # conventional torque path with the warning; held_share, method_ran and
        # hold_reason as the CSV's est_src and est_hold columns give them
        js = os.path.join(self.tmp, "f.json")
        csv_path = os.path.join(self.tmp, "f.csv")
        cmd = [DRIVE_SIL, "--scenario", SCENARIO, "--out", csv_path, "--summary", js,
               "--set", "identify.R_se_max_rel=1e-6", "--set", "identify.on_refusal=conventional"]
        subprocess.run(cmd, check=True, capture_output=True)
        with open(js) as f:
            summary = json.load(f)
        col = metrics.load_csv(csv_path)
        rows = [k for k, t in enumerate(col["t_s"]) if 0.8 <= t < 0.95]
        told = [k for k in rows if col["est_src"][k] == 0]
        self.assertAlmostEqual(summary["held_share"], len(told) / len(rows), delta=1e-12)
        self.assertEqual(summary["held_share"], 1.0)
        self.assertEqual(summary["method_ran"], "conventional")
        self.assertEqual(summary["hold_reason"], "STEP1_REFUSED")   # est_hold 0x140
        self.assertTrue(all(int(col["est_hold"][k]) == 0x140 for k in rows))
        # the paper's run learns: nothing on the told model in the window
        r = subprocess.run([DRIVE_SIL, "--scenario", SCENARIO, "--summary", "-"], check=True,
                           capture_output=True, text=True)
        learned = json.loads(r.stdout)
        self.assertEqual((learned["method_ran"], learned["held_share"], learned["hold_reason"]),
                         ("proposed", 0, ""))

    def test_bad_window_exits_2(self):
        r = subprocess.run([DRIVE_SIL, "--scenario", SCENARIO, "--summary", "-", "--window", "0.9:0.8"],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("--window", r.stderr)
        self.assertEqual(r.stdout, "")


@unittest.skipUnless(have_drive_sil(), f"{DRIVE_SIL} not built")
class Sweep(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()
        self.out = os.path.join(self.tmp, "sw")

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def rows(self):
        with open(os.path.join(self.out, sweep.RESULTS), newline="") as f:
            return list(csv.DictReader(f))

    def test_rows_equal_drive_sil_and_metrics_by_hand_at_fixed_points(self):
        rc, err = run_sweep("--scenario", SCENARIO, "--grid", "controller.L_factor=0.5:2:3",
                            "--grid", "controller.psif_factor=0.5:1:2", "--jobs", "2", "--out", self.out)
        self.assertEqual(rc, 0, err)
        rows = self.rows()
        self.assertEqual(len(rows), 3 * 2 * 2)
        # fixed picks: first, a middle and the last row
        for r in (rows[0], rows[5], rows[-1]):
            sets = [f"controller.L_factor={r['controller.L_factor']}",
                    f"controller.psif_factor={r['controller.psif_factor']}"] + sweep.METHOD_SETS[r["method"]]
            hand, col = by_hand(self.tmp, sets)
            for k, tol in TOL.items():
                self.assertAlmostEqual(float(r[k]), hand[k], delta=tol, msg=f"{k} at {sets}")
            self.assertEqual((r["final_state_name"], int(col["state"][-1])), ("RUN", APP_STATE_RUN))
            self.assertEqual(r["status"], "ok")
            self.assertAlmostEqual(float(r["controller.L_H"]), float(r["controller.L_factor"]) * TRUTH[1],
                                   delta=1e-12)

    def test_bad_key_and_bad_range_exit_2_naming_them_and_write_nothing(self):
        for grid, words in (("controller.nokey=1:2:3", ("controller.nokey", "unknown key")),
                            ("controller.L_factor=2:1:0", ("controller.L_factor=2:1:0", "N")),
                            ("controller.L_factor=0:1:3", ("controller.L_factor", "out of range")),
                            ("controller.L_factor=1:2:3:log:x", ("controller.L_factor",)),
                            ("speed=1:2:3", ("template",))):
            rc, err = run_sweep("--scenario", SCENARIO, "--grid", grid, "--out", self.out)
            self.assertEqual(rc, 2, grid)
            for w in words:
                self.assertIn(w, err, grid)
            self.assertFalse(os.path.exists(self.out), grid)

    def test_resume_skips_done_points_and_distrusts_a_cut_row(self):
        args = ("--scenario", SCENARIO, "--grid", "controller.L_factor=0.5:2:3", "--methods", "proposed",
                "--jobs", "1", "--out", self.out)
        self.assertEqual(run_sweep(*args)[0], 0)
        first = self.rows()
        path = os.path.join(self.out, sweep.RESULTS)
        with open(path) as f:
            lines = f.read().split("\n")
        # drop the last point, and leave the middle one cut short as an interrupted write would
        with open(path, "w") as f:
            f.write("\n".join(lines[:2]) + "\n" + lines[2][:40])
        rc, err = run_sweep(*args)
        self.assertEqual(rc, 0, err)
        self.assertIn("1 of 3 points already done", err)
        self.assertEqual(self.rows(), first)

    def test_a_changed_override_starts_afresh(self):
        args = ["--scenario", SCENARIO, "--grid", "controller.L_factor=1:1:1", "--methods", "proposed",
                "--out", self.out]
        self.assertEqual(run_sweep(*args)[0], 0)
        rc, err = run_sweep(*args, "--set", "controller.R_factor=1.5")
        self.assertEqual(rc, 0, err)
        self.assertIn("starting afresh", err)
        self.assertAlmostEqual(float(self.rows()[0]["controller.R_ohm"]), 4.5, delta=1e-9)


class SweepCheck(unittest.TestCase):
    """drivekit.sweep_check on hand-made results: each rule can fail."""

    def write(self, d, points):
        cols = sweep.columns([sweep.Grid("controller.L_factor=1:2:2", False)])
        with open(os.path.join(d, sweep.RESULTS), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols)
            for x, method, te, fault in points:
                r = {c: "1" for c in cols}
                r.update({"method": method, "controller.L_factor": x, "te_err_Nm": te, "fault_name": fault,
                          "final_state_name": "FAULT" if fault != "NONE" else "RUN", "status": "ok"})
                w.writerow([r[c] for c in cols])

    def run_check(self, points):
        with tempfile.TemporaryDirectory() as d:
            self.write(d, points)
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                rc = sweep_check.main([d, "--tol-Nm", "0.005"])
        return rc, out.getvalue()

    def test_within_the_tolerance_and_faults_of_both_pass(self):
        rc, out = self.run_check([("1", "conventional", "0.010", "NONE"), ("1", "proposed", "0.0149", "NONE"),
                                  ("2", "conventional", "0", "OVERCURRENT"), ("2", "proposed", "0", "HW_TRIP")])
        self.assertEqual(rc, 0, out)

    def test_worse_torque_and_a_fault_of_its_own_fail(self):
        rc, out = self.run_check([("1", "conventional", "0.010", "NONE"), ("1", "proposed", "0.0151", "NONE"),
                                  ("2", "conventional", "0.5", "NONE"), ("2", "proposed", "0", "CONFIG")])
        self.assertEqual(rc, 1)
        self.assertIn("0.0151 N m > conventional 0.0100", out)
        self.assertIn("proposed faulted (CONFIG)", out)

    def test_a_missing_method_fails(self):
        rc, out = self.run_check([("1", "proposed", "0.001", "NONE")])
        self.assertEqual(rc, 1)
        self.assertIn("not both methods ran", out)


class GridText(unittest.TestCase):
    def test_linear_and_log_values(self):
        self.assertEqual(sweep.Grid("a.b=1:3:3", False).values(), [1.0, 2.0, 3.0])
        v = sweep.Grid("a.b=0.5:2:3", True).values()
        for x, want in zip(v, (0.5, 1.0, 2.0)):
            self.assertAlmostEqual(x, want, places=12)
        self.assertEqual(sweep.Grid("a.b=0.5:2:3:lin", True).values(), [0.5, 1.25, 2.0])
        self.assertEqual(sweep.Grid("a.b=2:2:1", False).values(), [2.0])

    def test_bad_grids_name_the_problem(self):
        for text, word in (("a.b", "NAME=START"), ("a.b=1:2", "START:STOP:N"), ("a.b=x:2:3", "numbers"),
                           ("a.b=1:2:1", "N = 1"), ("a.b=1:2:-3", "N must"), ("a.b=0:2:3:log", "log"),
                           ("a.b=1:inf:3", "finite")):
            with self.assertRaises(sweep.BadInput) as cm:
                sweep.Grid(text, False)
            self.assertIn(word, str(cm.exception), text)

    def test_templates_fill_the_overrides(self):
        g = [sweep.Grid("load_Nm=1:2:2", False), sweep.Grid("controller.L_factor=1:1:1", False)]
        sets = sweep.point_sets(["load.torque_Nm=0:2, 0.6:{load_Nm}"], g, [2.0, 1.0], "proposed")
        self.assertEqual(sets, ["load.torque_Nm=0:2, 0.6:2.0", "controller.L_factor=1.0",
                                "controller.method=proposed"])
        self.assertEqual(sweep.point_sets([], g[1:], [1.0], "conventional"),
                         ["controller.L_factor=1.0", "controller.method=conventional", "identify.mode=off"])


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/env python3
"""tests/test_sil_plot.py - drivekit.sil_plot's command line under the
system python3 (no matplotlib needed): --help and argument errors before
matplotlib is imported, a clear message naming `make plot` and the venv
when it is missing, the output-name rule (RUN.csv -> RUN.png), the title
from the run's resolved values. Where build/venv exists, one real plot
through it (Agg: a file, no window)."""
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRIVEKIT = os.path.join(ROOT, "tools", "drivekit")
VENV_PY = os.path.join(ROOT, "build", "venv", "bin", "python")
sys.path.insert(0, DRIVEKIT)
from drivekit import sil_plot  # noqa: E402


class NoMatplotlib(unittest.TestCase):
    """A matplotlib package that fails to import stands first on the path,
    so these hold whether or not the system has one."""

    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        fake = os.path.join(self._tmp.name, "fake", "matplotlib")
        os.makedirs(fake)
        with open(os.path.join(fake, "__init__.py"), "w") as f:
            f.write("raise ImportError('no matplotlib (test)')\n")
        self.env = dict(os.environ, PYTHONPATH=os.pathsep.join((os.path.dirname(fake), DRIVEKIT)),
                        PYTHONDONTWRITEBYTECODE="1")

    def tearDown(self):
        self._tmp.cleanup()

    def run_plot(self, *args):
        return subprocess.run([sys.executable, "-m", "drivekit.sil_plot", *args], env=self.env, capture_output=True,
                              text=True,
                              cwd=self._tmp.name)

    def test_help(self):
        p = self.run_plot("--help")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("usage: sil_plot.py", p.stdout)
        self.assertIn("RUN.csv", p.stdout)

    def test_missing_matplotlib_is_named(self):
        p = self.run_plot("run.csv")
        self.assertEqual(p.returncode, 1)
        self.assertIn("matplotlib is not installed", p.stderr)
        self.assertIn("make plot CSV=RUN.csv", p.stderr)
        self.assertIn("build/venv/bin/sil-plot", p.stderr)
        self.assertNotIn("Traceback", p.stderr)

    def test_usage_errors_before_matplotlib(self):
        for args in ([], ["a.csv", "b.csv", "-o", "x.png"], ["--jobs", "0", "a.csv"]):
            p = self.run_plot(*args)
            self.assertEqual(p.returncode, 2, (args, p.stderr))
            self.assertIn("usage:", p.stderr)
            self.assertNotIn("matplotlib", p.stderr)

    def test_output_must_not_be_the_csv(self):
        p = self.run_plot("run.csv", "-o", "./run.csv")
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("would overwrite the CSV", p.stderr)


class OutputName(unittest.TestCase):
    def test_default_out(self):
        self.assertEqual(sil_plot.default_out("build/sil/prop_paper.csv"), "build/sil/prop_paper.png")
        self.assertEqual(sil_plot.default_out("/tmp/RUN.CSV"), "/tmp/RUN.png")
        self.assertEqual(sil_plot.default_out("a.b/run"), "a.b/run.png")           # no .csv: appended
        self.assertEqual(sil_plot.default_out("run.txt"), "run.txt.png")

    def test_arguments(self):
        a = sil_plot.parse_args(["x.csv"])
        self.assertEqual((a.csv, a.out, a.jobs), (["x.csv"], None, 1))
        a = sil_plot.parse_args(["x.csv", "-o", "y.svg"])
        self.assertEqual((a.csv, a.out), (["x.csv"], "y.svg"))
        a = sil_plot.parse_args(["x.csv", "y.png"])                                # the old form CSV PNG
        self.assertEqual((a.csv, a.out), (["x.csv"], "y.png"))
        a = sil_plot.parse_args(["--jobs", "2", "x.csv", "y.csv"])                 # two runs, two PNGs
        self.assertEqual((a.csv, a.out, a.jobs), (["x.csv", "y.csv"], None, 2))


class Title(unittest.TestCase):
    def test_title_from_the_scenario(self):
        r = {"scenario": "tools/scenarios/prop_L150.ini", "controller": {"method": "proposed", "mode": "speed"}}
        self.assertEqual(sil_plot.title_of("/tmp/x/out.csv", r), "prop_L150: proposed DB-DTC, speed mode")
        self.assertEqual(sil_plot.title_of("/tmp/x/out.csv", {"scenario": "a/b.ini"}), "b")
        self.assertEqual(sil_plot.title_of("/tmp/x/out.csv", None), "out")          # no resolved values

    def test_overrides_in_the_title(self):
        r = {"scenario": "tools/scenarios/prop_paper.ini", "overrides": ["plant.L_H=0.02", "run.duration_s=1"],
             "controller": {"method": "conventional", "mode": "speed"}}
        self.assertEqual(sil_plot.title_of("x.csv", r),
                         "prop_paper + plant.L_H=0.02, run.duration_s=1: conventional DB-DTC, speed mode")
        r["overrides"] = []
        self.assertEqual(sil_plot.title_of("x.csv", r), "prop_paper: conventional DB-DTC, speed mode")

    def test_commissioning_titled_as_such(self):
        # drive_sil --commission runs the conventional method's settings: not what the title names
        r = {"scenario": "a/conv_motor_paper.ini", "overrides": [], "commission": True,
             "controller": {"method": "conventional", "mode": "speed"}}
        self.assertEqual(sil_plot.title_of("x.csv", r), "conv_motor_paper: commissioning (measuring the motor)")

    def test_a_long_title_keeps_what_ran_on_its_own_line(self):
        sets = ["controller.L_factor=1.4", "controller.psif_factor=0.85", "plant.adc_noise_A=0.02"]
        r = {"scenario": "prop_paper.ini", "overrides": sets, "controller": {"method": "proposed", "mode": "speed"}}
        lines = sil_plot.title_of("x.csv", r).split("\n")
        self.assertEqual(lines[-1], "proposed DB-DTC, speed mode")
        self.assertEqual(" ".join(lines[:-1]), "prop_paper + " + ", ".join(sets))
        self.assertTrue(all(len(x) <= sil_plot.TITLE_WIDTH for x in lines))

    def test_resolved_beside_the_csv(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "run.resolved.json"), "w") as f:
                f.write('{"scenario": "s.ini"}')
            self.assertEqual(sil_plot.resolved_of(os.path.join(d, "run.csv")), {"scenario": "s.ini"})
            self.assertIsNone(sil_plot.resolved_of(os.path.join(d, "none.csv")))


class FakeAxis:
    """The y-limits of an axis, as span_floor reads and sets them."""
    def __init__(self, lo, hi):
        self.lim = (lo, hi)

    def get_ylim(self):
        return self.lim

    def set_ylim(self, lo, hi):
        self.lim = (lo, hi)


class SpanFloor(unittest.TestCase):
    def test_a_constant_estimate_spans_its_share_of_the_value(self):
        # float32 rounding of 0.24 Wb: a span of 1e-9 would print 0.239999996
        ax = FakeAxis(0.239999995, 0.240000001)
        sil_plot.span_floor(ax, [0.239999996, 0.24], 0.0001)
        lo, hi = ax.lim
        self.assertAlmostEqual(hi - lo, sil_plot.SPAN_REL * 0.24, places=12)   # 0.0024 Wb
        self.assertAlmostEqual(0.5 * (lo + hi), 0.239999998, places=9)         # about the middle

    def test_near_zero_the_panels_own_floor(self):
        ax = FakeAxis(-1e-6, 1e-6)
        sil_plot.span_floor(ax, [0.0, 1e-7], 0.01)
        self.assertAlmostEqual(ax.lim[1] - ax.lim[0], 0.01)

    def test_a_wide_range_is_left_alone(self):
        ax = FakeAxis(-5.0, 500.0)
        sil_plot.span_floor(ax, [0.0, 480.0, float("nan")], 1.0)
        self.assertEqual(ax.lim, (-5.0, 500.0))
        sil_plot.span_floor(ax, [float("nan")], 1.0)                             # nothing finite: unchanged
        self.assertEqual(ax.lim, (-5.0, 500.0))


class ReadErrors(unittest.TestCase):
    def test_bad_csv_named(self):
        with tempfile.TemporaryDirectory() as d:
            cases = {"empty.csv": ("", "no data rows"), "notsil.csv": ("a,b\n1,2\n", "no t_s column"),
                     "rows.csv": ("t_s,te_Nm\n", "no data rows"),
                     "short.csv": ("t_s,te_Nm\n0,1\n0.1\n", "short.csv:3: 1 fields, the header has 2"),
                     "text.csv": ("t_s,te_Nm\n0,x\n", "column te_Nm: malformed number 'x'")}
            for name, (text, msg) in cases.items():
                path = os.path.join(d, name)
                with open(path, "w") as f:
                    f.write(text)
                with self.assertRaises(sil_plot.PlotError) as cm:
                    sil_plot.read_columns(path)
                self.assertIn(msg, str(cm.exception))


@unittest.skipUnless(os.path.exists(VENV_PY), "no build/venv (make venv)")
class RealPlot(unittest.TestCase):
    def test_plot_through_the_venv(self):
        with tempfile.TemporaryDirectory() as d:
            csv_path = os.path.join(d, "run.csv")
            with open(csv_path, "w") as f:
                f.write("t_s,speed_ref_rpm,speed_rpm,R_est_ohm,L_est_H\n")
                for k in range(50):
                    f.write(f"{k * 1e-3},500,{500 - k * 0.01},3.0,{0.011 + 1e-9 * k}\n")
            env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1", DISPLAY="", MPLBACKEND="TkAgg", PYTHONPATH=DRIVEKIT)
            plot = [VENV_PY, "-m", "drivekit.sil_plot"]
            p = subprocess.run([*plot, csv_path], env=env, capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(p.stdout.strip(), "sil_plot: " + os.path.join(d, "run.png"))
            with open(os.path.join(d, "run.png"), "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
            p = subprocess.run([*plot, "-o", os.path.join(d, "other.svg"), csv_path],
                               env=env, capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertTrue(os.path.getsize(os.path.join(d, "other.svg")) > 0)


if __name__ == "__main__":
    unittest.main()

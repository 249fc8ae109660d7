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

    def test_import_does_not_load_matplotlib(self):
        code = ("import sys; sys.path.insert(0, sys.argv[1]); from drivekit import sil_plot; "
                "print('matplotlib' in sys.modules)")
        p = subprocess.run([sys.executable, "-B", "-c", code, DRIVEKIT], capture_output=True, text=True)
        self.assertEqual((p.returncode, p.stdout.strip()), (0, "False"), p.stderr)


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

    def test_resolved_beside_the_csv(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "run.resolved.json"), "w") as f:
                f.write('{"scenario": "s.ini"}')
            self.assertEqual(sil_plot.resolved_of(os.path.join(d, "run.csv")), {"scenario": "s.ini"})
            self.assertIsNone(sil_plot.resolved_of(os.path.join(d, "none.csv")))


class ReadErrors(unittest.TestCase):
    def test_bad_csv_named(self):
        with tempfile.TemporaryDirectory() as d:
            cases = {"empty.csv": ("", "empty file"), "notsil.csv": ("a,b\n1,2\n", "no t_s column"),
                     "rows.csv": ("t_s,te_Nm\n", "no data rows"),
                     "short.csv": ("t_s,te_Nm\n0,1\n0.1\n", "short.csv:3: 1 fields, header has 2"),
                     "text.csv": ("t_s,te_Nm\n0,x\n", "column te_Nm: not a number")}
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

#!/usr/bin/env python3
"""tests/test_sil_report.py - the table logic of drivekit.sil_report (no
plotting): pairing conv_/prop_ runs into cases, the rows of both tables,
exact plot links, windows and the plant's true values. Standard library
only: sil_report imports matplotlib only inside load_matplotlib(), and the
end-to-end run below replaces that with "not available"."""
import contextlib
import io
import json
import os
import sys
import tempfile
import unittest
from unittest import mock

DRIVEKIT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools", "drivekit")
sys.path.insert(0, DRIVEKIT)
from drivekit import sil_report  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_metrics import HEADER, DEFAULTS, cell, t_of  # noqa: E402


def result(**kw):
    """A metrics.compute() result with every figure the tables read."""
    r = {"te_err_Nm": 0.0123, "te_ripple_Nm": 0.0234, "psi_err_Wb": 0.0025, "psi_err_pct": 1.0,
         "speed_err_rpm": -0.5, "speed_err_max_rpm": 1.5, "id_A": -1.5, "iq_A": 3.5}
    r.update(kw)
    return r


def cells(line):
    """Cells of a markdown table row ('\\|' inside a cell is no separator)."""
    parts = line.replace("\\|", "\0").split("|")
    assert parts[0] == "" and parts[-1] == "", line
    return [p.strip().replace("\0", "|") for p in parts[1:-1]]


class Tmp(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.dir = self._tmp.name

    def tearDown(self):
        self._tmp.cleanup()

    def touch(self, *names):
        for n in names:
            open(os.path.join(self.dir, n), "w").close()


class PairCases(unittest.TestCase):
    def test_pairs(self):
        r = {name: result() for name in ("conv_L066", "prop_L066", "conv_L066_psif150",
                                         "prop_L066_psif150", "conv_R430", "prop_psif050",
                                         "open_loop_steady", "conv_paper", "convL066")}
        r["prop_paper"] = {"error": "x.csv: no data rows"}
        cases = sil_report.pair_cases(r)
        # R430 and psif050 lack a partner, paper's proposed run failed, open_loop_* and
        # convL066 are no method's runs; L066 and L066_psif150 are distinct cases
        self.assertEqual([c for c, _ in cases], ["L066", "L066_psif150"])
        by = dict(cases)
        self.assertIs(by["L066"]["conv"], r["conv_L066"])
        self.assertIs(by["L066"]["prop"], r["prop_L066"])
        self.assertIs(by["L066_psif150"]["conv"], r["conv_L066_psif150"])
        self.assertIs(by["L066_psif150"]["prop"], r["prop_L066_psif150"])

    def test_none(self):
        self.assertEqual(sil_report.pair_cases({"conv_a": result(), "open_loop": result()}), [])


class PlotLinks(Tmp):
    def test_exact_stem(self):
        self.touch("conv_L066.png", "conv_L066_psif150.png", "conv_L066_psif150.svg",
                   "prop_L066_step1.png", "prop_L066_psif150.png", "prop_L066_psif150_step1.png")
        d = self.dir
        self.assertEqual(sil_report.plot_links(d, "conv_L066"), "[conv_L066.png](conv_L066.png)")
        self.assertEqual(sil_report.plot_links(d, "conv_L066_psif150"),
                         "[conv_L066_psif150.png](conv_L066_psif150.png) "
                         "[conv_L066_psif150.svg](conv_L066_psif150.svg)")
        self.assertEqual(sil_report.plot_links(d, "prop_L066"), "[prop_L066_step1.png](prop_L066_step1.png)")
        self.assertEqual(sil_report.plot_links(d, "prop_L066_psif150"),
                         "[prop_L066_psif150.png](prop_L066_psif150.png) "
                         "[prop_L066_psif150_step1.png](prop_L066_psif150_step1.png)")
        self.assertEqual(sil_report.plot_links(d, "conv_L06"), "-")


class ScenarioTable(Tmp):
    RUNS = [("conv_L066", result(recovery_ms=12.0, speed_dip_rpm=77.58)),
            ("conv_torque_step", result(speed_err_rpm=float("nan"), speed_err_max_rpm=float("nan"),
                                        step_periods_95=2, step_overshoot_pct=0.3564,
                                        step_settle_periods=None)),
            ("broken", {"error": "broken.csv:3: column te_Nm: malformed number 'a|b'"})]

    def test_rows(self):
        self.touch("conv_L066.png", "conv_L066_psif150.png")
        lines = sil_report.scenario_table(self.RUNS, self.dir)
        n = len(cells(lines[0]))
        self.assertEqual(n, 8)
        for line in lines[1:]:
            self.assertEqual(len(cells(line)), n, line)     # every row as wide as the header
        self.assertEqual(cells(lines[2]), [
            "conv_L066", "0.0123", "0.0234", "2.50", "1.000", "-0.500", "1.500", "[conv_L066.png](conv_L066.png)"])
        self.assertEqual(cells(lines[3]), [
            "conv_torque_step", "0.0123", "0.0234", "2.50", "1.000", "-", "-", "-"])
        self.assertEqual(cells(lines[4])[:2], ["broken", "error: broken.csv:3: column te_Nm: malformed number 'a|b'"])
        self.assertEqual(cells(lines[4])[2:], [""] * 6)

    def test_response_rows(self):
        lines = sil_report.scenario_response_table(self.RUNS)
        n = len(cells(lines[0]))
        self.assertEqual(n, 8)
        self.assertEqual(len(lines), 2 + 2)                 # the failed run is named in the first table only
        for line in lines[1:]:
            self.assertEqual(len(cells(line)), n, line)
        self.assertEqual(cells(lines[2]), ["conv_L066", "-1.5000", "3.5000", "12.0", "77.58", "-", "-", "-"])
        self.assertEqual(cells(lines[3]), ["conv_torque_step", "-1.5000", "3.5000", "-", "-", "2", "0.36", "-"])


class CaseTable(Tmp):
    CASES = [("L066", {"conv": result(), "prop": result(R_err_pct=0.013, L_err_pct=0.0, psif_err_pct=-0.01,
                                                       t2_L_ms=19.0, t2_psif_ms=None, speed_dip_rpm=75.88)}),
             ("L066_psif150", {"conv": result(L_err_pct=-34.0, psif_err_pct=50.0, t2_L_ms=None),
                               "prop": result(step_periods_95=2, step_overshoot_pct=0.23)})]

    def test_rows(self):
        self.touch("L066_psif150_compare.png")
        cases = self.CASES
        real = {"real_conv_L066": result(te_err_Nm=0.08), "real_prop_L066": result(te_err_Nm=0.02),
                "real_conv_L066_psif150": {"error": "failed"}, "real_prop_L066_psif150": result(te_err_Nm=0.03)}
        lines = sil_report.case_table(cases, self.dir, real)
        n = len(cells(lines[0]))
        self.assertEqual(n, 10)
        self.assertEqual(len(lines), 2 + 4)
        for line in lines[1:]:
            self.assertEqual(len(cells(line)), n, line)
        rows = [cells(line) for line in lines[2:]]
        self.assertEqual([r[:2] for r in rows], [["L066", "conventional"], ["L066", "proposed"],
                                                 ["L066_psif150", "conventional"], ["L066_psif150", "proposed"]])
        self.assertEqual(rows[1][2:], ["0.0123", "0.0200", "0.25", "1.000", "0.0234", "75.88", "-", "paper"])
        self.assertEqual(rows[0][3:5], ["0.0800", "-"])        # the conventional row has no ratio
        self.assertEqual(rows[2][3:5], ["-", "-"])             # its realistic run failed: no ratio either
        self.assertEqual(rows[3][3:5], ["0.0300", "-"])
        self.assertEqual(cells(sil_report.case_table(cases[:1], self.dir)[2])[3:5], ["-", "-"])   # no real runs
        # L066 has no comparison figure: no link, and not L066_psif150's
        self.assertEqual([r[-2] for r in rows], ["-", "-", "[L066_psif150_compare.png](L066_psif150_compare.png)",
                                                 "[L066_psif150_compare.png](L066_psif150_compare.png)"])

    def test_small_ratio_keeps_its_digits(self):
        # 0.00022 / 0.05 = 0.0044: two significant digits, not "0.00"
        real = {"real_conv_L066": result(te_err_Nm=0.05), "real_prop_L066": result(te_err_Nm=0.00022)}
        rows = [cells(x) for x in sil_report.case_table(self.CASES[:1], self.dir, real)[2:]]
        self.assertEqual(rows[1][3:5], ["0.0002", "0.0044"])

    def test_estimate_rows(self):
        lines = sil_report.estimate_table(self.CASES)
        n = len(cells(lines[0]))
        self.assertEqual(n, 10)
        self.assertEqual(len(lines), 2 + 4)
        for line in lines[1:]:
            self.assertEqual(len(cells(line)), n, line)
        rows = [cells(line) for line in lines[2:]]
        self.assertEqual(rows[1], ["L066", "proposed", "+0.013", "+0.000", "-0.010", "19.0", "-", "-", "-", "paper"])
        self.assertEqual(rows[2][2:5], ["-", "-34.000", "+50.000"])
        self.assertEqual(rows[3][7:9], ["2", "0.23"])


class Significant(unittest.TestCase):
    def test_sig(self):
        cases = [(0.0044, "0.0044"), (0.004449, "0.0044"), (0.25, "0.25"), (1.25, "1.2"), (0.999, "1.0"),
                 (9.96, "10"), (0.0995, "0.10"), (12.3, "12"), (123.4, "123"), (0.0, "0"), (-0.0044, "-0.0044"),
                 (None, "-"), (float("nan"), "-"), (float("inf"), "-")]
        for v, text in cases:
            self.assertEqual(sil_report.sig(v), text, v)
        self.assertEqual(sil_report.sig(0.012345, 3), "0.0123")


class SeedTable(Tmp):
    def write_seeds(self, stem, lines):
        os.makedirs(os.path.join(self.dir, "seeds"), exist_ok=True)
        with open(os.path.join(self.dir, "seeds", stem + ".jsonl"), "w") as f:
            f.write("\n".join(lines) + "\n")

    def test_rows(self):
        self.assertEqual(sil_report.seed_table(self.dir), [])          # no seeds/: no section
        # median of 0.010, 0.012, 0.013, 0.031 (the two middle ones): 0.0125
        self.write_seeds("real_prop_A", [json.dumps({"id": "seed%d" % k, "te_err_Nm": v})
                                         for k, v in enumerate((0.013, 0.012, 0.031, 0.010), 1)])
        self.write_seeds("real_conv_A", [
            json.dumps({"id": "seed1", "te_err_Nm": 0.06}),
            json.dumps({"id": "seed2", "error": "--set plant.seed=x: not a whole number"}),
            json.dumps({"id": "seed3", "te_err_Nm": None}),
            "not json",
            json.dumps({"id": "seed5", "te_err_Nm": 0.05})])
        self.write_seeds("real_prop_B", [json.dumps({"id": "seed1", "error": "failed"})])
        lines = sil_report.seed_table(self.dir)
        self.assertEqual(len(lines), 2 + 3)
        n = len(cells(lines[0]))
        for line in lines[1:]:
            self.assertEqual(len(cells(line)), n, line)
        rows = [cells(line) for line in lines[2:]]
        self.assertEqual(rows[0], ["real_conv_A", "5", "0.0500", "0.0550", "0.0600", "seed1", "seed2 seed3 ?"])
        self.assertEqual(rows[1], ["real_prop_A", "4", "0.0100", "0.0125", "0.0310", "seed3", "-"])
        self.assertEqual(rows[2], ["real_prop_B", "1", "-", "-", "-", "-", "seed1"])


class WindowsAndTruth(Tmp):
    def test_windows(self):
        self.assertEqual(sil_report.windows({"t_s": [0.0, 1.0, 1.05]}), ((0.8, 0.95), (0.95, 1.05)))
        self.assertEqual(sil_report.windows({"t_s": [0.0, 1.1999]}), ((0.8, 0.95), (0.95, 1.05)))
        (a, b), load = sil_report.windows({"t_s": [0.0, 0.2]})      # a short run: its last quarter
        self.assertAlmostEqual(a, 0.15, places=12)
        self.assertAlmostEqual(b, 0.2 + 1e-9, places=15)
        self.assertIsNone(load)
        win, load = sil_report.windows({"t_s": [0.0, 2.9999]})     # a long run: its last 0.5 s, no load window
        self.assertAlmostEqual(win[0], 2.4999, places=9)
        self.assertIsNone(load)

    def test_motor_column(self):
        cases = [("motor_small", {"conv": result(), "prop": result()}),
                 ("motor_large_timeline", {"conv": result(), "prop": result()}),
                 ("L066", {"conv": result(), "prop": result()})]
        for table in (sil_report.case_table(cases, self.dir), sil_report.estimate_table(cases)):
            self.assertEqual([cells(x)[-1] for x in table[2:]],
                             ["small", "small", "large", "large", "paper", "paper"])

    def write_resolved(self, stem, plant):
        with open(os.path.join(self.dir, stem + ".resolved.json"), "w") as f:
            json.dump({"scenario": stem + ".ini", "plant": plant, "controller": {"R_ohm": 3.0}}, f)

    def test_truth_of(self):
        # the run's resolved plant (drive_sil's OUT.resolved.json), --set included; not the INI
        self.write_resolved("x", {"R_ohm": 12.9, "L_H": 0.0165, "psif_Wb": 0.24})
        with open(os.path.join(self.dir, "x.ini"), "w") as f:
            f.write("[plant]\nR_ohm = 1.0\n")
        self.assertEqual(sil_report.truth_of(self.dir, "x"), (12.9, 0.0165, 0.24))
        with self.assertRaisesRegex(ValueError, r"none\.resolved\.json: no resolved values"):
            sil_report.truth_of(self.dir, "none")
        with open(os.path.join(self.dir, "bad.resolved.json"), "w") as f:
            f.write('{"plant": {"R_ohm": 3.0}}')
        with self.assertRaisesRegex(ValueError, r"bad\.resolved\.json: not drive_sil's resolved values"):
            sil_report.truth_of(self.dir, "bad")


class Main(Tmp):
    """End to end without matplotlib: CSVs in, report.md out."""

    def write_run(self, name, te_off, n=120, te_ref=4.0):
        with open(os.path.join(self.dir, name + ".resolved.json"), "w") as f:
            json.dump({"plant": {"R_ohm": 3.0, "L_H": 0.011, "psif_Wb": 0.24}}, f)
        with open(os.path.join(self.dir, name + ".csv"), "w") as f:
            f.write(",".join(HEADER) + "\n")
            for k in range(n):
                row = dict(DEFAULTS, t_s=t_of(k, 0.01), te_ref_Nm=te_ref, te_Nm=te_ref + te_off)
                f.write(",".join(cell(row[h]) for h in HEADER) + "\n")

    def run_main(self):
        out, err = io.StringIO(), io.StringIO()
        with mock.patch.object(sil_report, "load_matplotlib", return_value=None), \
                contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            rc = sil_report.main(["--dir", self.dir, "--scenarios", self.dir])
        with open(os.path.join(self.dir, "report.md")) as f:
            return rc, out.getvalue(), f.read()

    def test_report(self):
        # t = 0 .. 1.19 s: paper windows; Te - Te* = 0.01 (conv) and 0.002 (prop)
        self.write_run("conv_A", 0.01)
        self.write_run("prop_A", 0.002)
        self.write_run("conv_B", 0.01)
        rc, out, rep = self.run_main()
        self.assertEqual(rc, 0)
        self.assertIn("(3 scenarios, 1 cases)", out)
        lines = rep.splitlines()
        case_rows = [cells(x) for x in lines if x.startswith("| A |")]
        # the torque table, then the estimates' table
        self.assertEqual([r[1:3] for r in case_rows], [["conventional", "0.0100"], ["proposed", "0.0020"],
                                                       ["conventional", "+0.000"], ["proposed", "+0.000"]])
        self.assertLess(lines.index("## Case x method"), lines.index("### Estimates and torque step"))
        self.assertIn("(matplotlib not available: comparison and step-1 figures not drawn)", lines)
        scen = [cells(x)[:2] for x in lines if x.startswith(("| conv_", "| prop_"))]
        # the errors' table, then the currents' (id_A = 0 in DEFAULTS)
        self.assertEqual(scen, [["conv_A", "0.0100"], ["conv_B", "0.0100"], ["prop_A", "0.0020"],
                                ["conv_A", "+0.0000"], ["conv_B", "+0.0000"], ["prop_A", "+0.0000"]])
        self.assertNotIn("## Realistic board over noise seeds", lines)   # no seeds/ runs

    def test_report_with_seeds(self):
        self.write_run("conv_A", 0.01)
        self.write_run("prop_A", 0.002)
        os.makedirs(os.path.join(self.dir, "seeds"))
        with open(os.path.join(self.dir, "seeds", "real_prop_A.jsonl"), "w") as f:
            f.write(json.dumps({"id": "seed1", "te_err_Nm": 0.02}) + "\n")
        rc, out, rep = self.run_main()
        self.assertEqual(rc, 0)
        self.assertIn("(2 scenarios, 1 cases)", out)                   # seeds/ holds no scenario CSV
        lines = rep.splitlines()
        head = lines.index("## Realistic board over noise seeds")
        self.assertLess(head, lines.index("## Every scenario"))
        rows = [cells(x) for x in lines if x.startswith("| real_prop_A |")]
        self.assertEqual(rows, [["real_prop_A", "1", "0.0200", "0.0200", "0.0200", "seed1", "-"]])

    def test_failed_run(self):
        self.write_run("conv_A", 0.01)
        with open(os.path.join(self.dir, "prop_A.csv"), "w") as f:
            f.write(",".join(HEADER) + "\n")          # header only: the run died
        rc, out, rep = self.run_main()
        self.assertEqual(rc, 1)
        self.assertIn("1 failed", out)
        self.assertIn("(no case with both conv_ and prop_ runs)", rep)
        row = [cells(x) for x in rep.splitlines() if x.startswith("| prop_A |")]
        self.assertEqual(len(row), 1)
        self.assertRegex(row[0][1], r"^error: .*prop_A\.csv: no data rows$")

    def test_no_csv(self):
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            self.assertEqual(sil_report.main(["--dir", self.dir]), 1)
        self.assertIn("no CSV in", err.getvalue())


class StaleFigures(Tmp):
    """Figures are drawn only when older than their runs: a report after one
    run changed redraws that run's figures, not all of them."""
    write_run = Main.write_run

    def figures_of_main(self, *extra):
        drawn = []
        with mock.patch.object(sil_report, "draw_figures", lambda figs, jobs: drawn.extend(figs) or True), \
                contextlib.redirect_stdout(io.StringIO()):
            self.assertEqual(sil_report.main(["--dir", self.dir, *extra]), 0)
        return sorted(os.path.basename(args[-1]) for _, args in drawn)

    def test_only_stale(self):
        for case in ("A", "B"):
            self.write_run("conv_" + case, 0.01)
            self.write_run("prop_" + case, 0.002)
        self.assertEqual(self.figures_of_main(), ["A_compare.png", "B_compare.png"])
        later = os.path.getmtime(os.path.join(self.dir, "prop_B.csv")) + 10
        for case in ("A", "B"):
            self.touch(case + "_compare.png")
            os.utime(os.path.join(self.dir, case + "_compare.png"), (later, later))
        self.assertEqual(self.figures_of_main(), [])
        os.utime(os.path.join(self.dir, "prop_B.csv"), (later + 1, later + 1))   # run B again
        self.assertEqual(self.figures_of_main(), ["B_compare.png"])
        self.assertEqual(self.figures_of_main("--figures", "all"), ["A_compare.png", "B_compare.png"])
        self.assertEqual(self.figures_of_main("--figures", "none"), [])


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/env python3
"""tests/test_campaign.py - drive-campaign (tools/drivekit/): the draws
recomputed by hand from (seed, index), the [campaign] section's checks,
the resume, an interrupt, the Dask path against the local one value by
value, the reproducers against drive_sil and rule-check, and bad
input. `make test-tools` runs it with DRIVE_SIL set and drive-campaign
installed in the venv (the end-to-end tests skip without drive_sil).

The campaigns run on the paper's motor (tools/scenarios/prop_paper.ini)
with a shorter timeline in their [campaign] section, a few draws each.
"""
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from statistics import NormalDist

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools", "drivekit"))
from drivekit import campaign_spec as cs  # noqa: E402
from drivekit import campaign_worker  # noqa: E402

import numpy as np  # noqa: E402

DRIVE_SIL = os.path.abspath(os.environ.get("DRIVE_SIL", os.path.join(ROOT, "build", "host", "drive_sil")))
VENV_SCRIPT = os.path.join(os.path.dirname(sys.executable), "drive-campaign")
PAPER = os.path.join(ROOT, "tools", "scenarios", "prop_paper.ini")
SHORT = ("\n[campaign]\n; a short timeline for the tests\nsettle_s = 0.1\nrecover_s = 0.1\nwindow_s = 0.1\n"
         "deadtime_s = uniform 0 0.5e-6   ; an override\n")
# A motor as motor_data() makes it, for the spec's own tests (the paper's, by hand).
MOTOR = {"R_ohm": 3.0, "L_H": 0.011, "psif_Wb": 0.24, "pole_pairs": 3, "J_kgm2": 0.00129, "vdc_V": 311.0,
         "adc_full_scale_A": 15.0, "encoder_offset_el_rad": 0.0, "i_rated_A": 5.55555582, "n_rated_rpm": 2000.0,
         "mode": "speed", "identify_mode": "windows", "duration_s": 1.2,
         "speed_profile": [[0, 0, False], [0.2, 500, True]], "load_profile": [[0, 2, False], [0.35, 4, False]],
         "told_absolute": {"R_ohm": False, "L_H": False, "psif_Wb": False}, "t_run_s": 0.5416, "Ts_s": 1e-4,
         "file_window": "0.8:1.2", "T_rated_Nm": 1.5 * 3 * 0.24 * 5.55555582}
ENV = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS", "MAKEOVERRIDES")}


def have_drive_sil():
    return os.path.isfile(DRIVE_SIL) and os.access(DRIVE_SIL, os.X_OK)


def campaign_cmd():
    if os.access(VENV_SCRIPT, os.X_OK):
        return [VENV_SCRIPT]
    return [sys.executable, "-m", "drivekit.campaign"]


def run_campaign(*args, **kw):
    env = dict(ENV, PYTHONPATH=os.path.join(ROOT, "tools", "drivekit"), PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run(campaign_cmd() + ["--drive-sil", DRIVE_SIL, "--quiet", *args], capture_output=True,
                          text=True, cwd=ROOT, env=env, **kw)


def read_rows(out):
    import pyarrow.parquet as pq
    return pq.read_table(os.path.join(out, "results.parquet")).to_pylist()


def spec_of(extra=""):
    return cs.Spec("motor.ini", "[plant]\n" + extra, MOTOR)


class Draws(unittest.TestCase):
    """A draw's inputs from (seed, index) alone, recomputed here from numpy's SeedSequence and the
    inverse CDFs written out by hand."""

    def u(self, seed, index, slot):
        w = np.random.SeedSequence(seed, spawn_key=(index,)).generate_state(cs.N_SLOTS, np.uint64)[slot]
        return ((int(w) >> 11) + 0.5) / 2.0 ** 53, int(w)

    def test_inputs_recomputed_by_hand(self):
        spec = spec_of()
        seed, i = 11, 7
        x = spec.inputs(seed, i)
        lsb = 2 * 15.0 / 4096
        u = {k.name: self.u(seed, i, k.slots[0])[0] for k in cs.DIST_KEYS}
        self.assertEqual(spec.text["deadtime_s"], "uniform 0 1e-06")      # 1 % of the PWM period
        self.assertEqual(x["deadtime_s"], 1e-6 * u["deadtime_s"])
        self.assertAlmostEqual(x["R_factor"], math.exp(math.log(0.65) + u["R_factor"] * math.log(1.1 / 0.65)),
                               delta=1e-15)
        self.assertAlmostEqual(x["psif_factor"], 0.95 + 0.24 * u["psif_factor"], delta=1e-15)
        # the defaults' texts hold the derived spreads to 4 digits, and are what the draws use
        self.assertEqual(spec.text["adc_offset_A"], "normal 0 0.0293")             # 4 LSB of +-15 A
        self.assertAlmostEqual(4 * lsb, 0.0293, delta=5e-6)
        self.assertAlmostEqual(x["adc_offset_a_A"], 0.0293 * NormalDist().inv_cdf(u["adc_offset_A"]), delta=1e-15)
        u_b = self.u(seed, i, cs.KEY_BY_NAME["adc_offset_A"].slots[1])[0]
        self.assertAlmostEqual(x["adc_offset_b_A"], 0.0293 * NormalDist().inv_cdf(u_b), delta=1e-15)
        self.assertEqual(spec.text["encoder_offset_err_el_rad"], "normal 0 0.02618")   # 0.5 mech. deg x 3
        self.assertAlmostEqual(3 * math.radians(0.5), 0.02618, delta=5e-7)
        self.assertAlmostEqual(x["encoder_offset_err_el_rad"],
                               0.02618 * NormalDist().inv_cdf(u["encoder_offset_err_el_rad"]), delta=1e-15)
        self.assertEqual(x["encoder_lines"], [1000, 2048, 2500, 4096][int(4 * u["encoder_lines"])])
        self.assertEqual(x["transient"], ["none", "load_step", "speed_step"][int(3 * u["transient"])])
        self.assertEqual(x["noise_seed"], self.u(seed, i, 0)[1] & 0xFFFFFFFF)
        self.assertAlmostEqual(x["speed_rpm"], 2000 * (0.1 + 0.8 * u["speed_frac"]), delta=1e-9)
        self.assertAlmostEqual(x["load_Nm"], 1.5 * 3 * 0.24 * 5.55555582 * (0.1 + 0.9 * u["load_frac"]),
                               delta=1e-12)

    def test_a_draw_depends_on_seed_and_index_only(self):
        spec = spec_of()
        forward = [spec.inputs(3, i) for i in range(12)]
        backward = [spec_of().inputs(3, i) for i in reversed(range(12))][::-1]
        self.assertEqual(forward, backward)
        self.assertNotEqual(spec.inputs(3, 5), spec.inputs(4, 5))
        self.assertNotEqual(spec.inputs(3, 5), spec.inputs(3, 6))

    def test_an_override_leaves_the_other_inputs(self):
        a = spec_of().inputs(5, 9)
        b = spec_of("[campaign]\nL_factor = uniform 2 3\n").inputs(5, 9)
        self.assertTrue(2 <= b["L_factor"] <= 3)
        self.assertEqual({k: v for k, v in a.items() if k != "L_factor"},
                         {k: v for k, v in b.items() if k != "L_factor"})

    def test_distributions_over_many_draws(self):
        spec = spec_of("[campaign]\nJ_factor = lognormal 1.5 1.2\nadc_offset_A = normal 0.01 0.002\n"
                       "encoder_lines = choice 1000 2500 2500\n")
        xs = [spec.inputs(1, i) for i in range(3000)]
        n = len(xs)

        def col(c):
            return np.array([x[c] for x in xs], dtype=float)
        dt = col("deadtime_s")
        self.assertTrue(dt.min() >= 0 and dt.max() <= 1e-6)
        self.assertLess(abs(dt.mean() - 0.5e-6), 4 * 1e-6 / math.sqrt(12 * n))
        logr = np.log(col("R_factor"))
        lo, hi = math.log(0.65), math.log(1.1)
        self.assertTrue(logr.min() >= lo and logr.max() <= hi)
        self.assertLess(abs(logr.mean() - (lo + hi) / 2), 4 * (hi - lo) / math.sqrt(12 * n))
        logj = np.log(col("J_factor"))          # lognormal: log normal(log 1.5, log 1.2)
        self.assertLess(abs(logj.mean() - math.log(1.5)), 4 * math.log(1.2) / math.sqrt(n))
        self.assertLess(abs(logj.std() / math.log(1.2) - 1), 0.08)
        v = col("adc_offset_b_A")
        self.assertLess(abs(v.mean() - 0.01), 4 * 0.002 / math.sqrt(n))
        self.assertLess(abs(v.std() / 0.002 - 1), 0.08)
        share = float((col("encoder_lines") == 2500).mean())
        self.assertLess(abs(share - 2 / 3), 4 * math.sqrt(2 / 9 / n))
        self.assertEqual(set(col("encoder_lines")), {1000.0, 2500.0})

    def test_overrides_of_a_draw(self):
        spec = spec_of()
        x = spec.inputs(1, 0)
        sets = dict(s.split("=", 1) for s in spec.overrides(x))
        self.assertEqual(float(sets["plant.deadtime_s"]), x["deadtime_s"])
        self.assertEqual(float(sets["controller.deadtime_s"]), x["deadtime_comp"] * x["deadtime_s"])
        self.assertEqual(float(sets["controller.R_factor"]), x["R_factor"])
        self.assertEqual(float(sets["controller.J_kgm2"]), x["J_factor"] * 0.00129)
        self.assertEqual(sets["run.duration_s"], f"{spec.duration_s:g}")
        # the timeline: start 0.6 s (step 1 ends 0.5416 s), ramp J n_rated / (T_rated / 4) = 0.18 s
        self.assertEqual((spec.start_s, spec.ramp_s, spec.event_s), (0.6, 0.19, 1.09))
        self.assertEqual(spec.window, "1.58:1.78")
        speed = sets["reference.speed_rpm"].split(", ")
        self.assertEqual(speed[:3], ["0:0", "0.2:500~", "0.6:500.0"])
        self.assertTrue(speed[3].startswith("0.79:") and speed[3].endswith("~"))
        told = dict(MOTOR, told_absolute={"R_ohm": True, "L_H": False, "psif_Wb": False})
        sets = dict(s.split("=", 1) for s in cs.Spec("m.ini", "", told).overrides(x))
        self.assertEqual(float(sets["controller.R_ohm"]), x["R_factor"] * 3.0)
        self.assertNotIn("controller.R_factor", sets)

    def test_profile_eval_steps_and_ramps(self):
        p = [[0.1, 2, False], [0.3, 6, True], [0.5, 1, False]]
        self.assertEqual([cs._profile_eval(p, t) for t in (0.0, 0.1, 0.2, 0.3, 0.45, 0.5, 9)],
                         [0.0, 2.0, 4.0, 6.0, 6.0, 1.0, 1.0])
        self.assertEqual(cs._profile_eval([[0.2, 500, True]], 0.1), 250.0)


class SpecChecks(unittest.TestCase):
    def bad(self, section, *words):
        with self.assertRaises(cs.SpecError) as cm:
            cs.Spec("m.ini", "[plant]\nR_ohm = 3\n[campaign]\n" + section, MOTOR)
        for w in words:
            self.assertIn(w, str(cm.exception))
        return str(cm.exception)

    def test_bad_sections_named(self):
        self.bad("R_fator = 1\n", "m.ini:4", "R_fator", "unknown key")
        self.bad("R_factor = 1\nR_factor = 2\n", "m.ini:5", "given twice")
        self.bad("R_factor = gaussian 1 2\n", "m.ini:4", "R_factor", "unknown distribution")
        self.bad("R_factor = uniform 2 1\n", "R_factor", "low end above the high end")
        self.bad("R_factor = normal 1 0.1\n", "R_factor", "<= 0")
        self.bad("L_factor = uniform 1 x\n", "L_factor", "\"x\" is not a number")
        self.bad("L_factor = uniform 1\n", "L_factor", "takes 2 numbers")
        self.bad("deadtime_comp = uniform 0 1.5\n", "deadtime_comp", "outside 0..1")
        self.bad("adc_noise_A = uniform -1 1\n", "adc_noise_A", "< 0")
        self.bad("encoder_lines = choice 1000 2500.5\n", "encoder_lines", "whole")
        self.bad("encoder_lines = uniform 1000 2000\n", "encoder_lines", "fixed N or choice")
        self.bad("transient = choice none jump\n", "transient", "unknown transient \"jump\"")
        self.bad("lognormal = 1\n", "unknown key")
        self.bad("speed_frac = lognormal 1 0.5\n", "GSD >= 1")
        self.bad("timeline = later\n", "timeline", "one of: drawn, file")
        self.bad("timeline = file\nwindow = 1:2\n", "window", "ends after the file's run")
        self.bad("ramp_s = 0\n", "ramp_s", "> 0")
        self.bad("just words\n", "m.ini:4", "expected key = distribution")

    def test_drawn_timeline_needs_the_speed_loop(self):
        with self.assertRaises(cs.SpecError) as cm:
            cs.Spec("m.ini", "", dict(MOTOR, mode="torque"))
        self.assertIn("timeline = file", str(cm.exception))

    def test_good_section_with_comments_and_continuation(self):
        spec = cs.Spec("m.ini", "[campaign]\n; note\nL_factor = choice 0.8 ; comment\n  1.2\n"
                       "transient = none\ntimeline = drawn\n", MOTOR)
        self.assertEqual(spec.dists["L_factor"].values, [0.8, 1.2])
        self.assertEqual({spec.inputs(1, i)["transient"] for i in range(20)}, {"none"})
        self.assertEqual(spec.source["L_factor"], "m.ini:3")

    def test_keys_document_is_the_table(self):
        with open(os.path.join(ROOT, "tools", "drivekit", "CAMPAIGN_KEYS.md")) as f:
            self.assertEqual(f.read(), cs.keys_markdown(), "make campaign-keys rewrites it")


class Worker(unittest.TestCase):
    def test_another_build_refused(self):
        with tempfile.NamedTemporaryFile() as f:
            f.write(b"not drive_sil")
            f.flush()
            with self.assertRaises(RuntimeError) as cm:
                campaign_worker.executable({"path": f.name, "sha256": "0" * 64})
            self.assertIn("another build", str(cm.exception))

    def test_shipped_build_written_once_by_hash(self):
        data = b"#!/bin/sh\necho shipped\n"
        sha = __import__("hashlib").sha256(data).hexdigest()
        p = campaign_worker.executable({"data": data, "sha256": sha})
        self.assertEqual(campaign_worker.executable({"data": data, "sha256": sha}), p)
        self.assertEqual(subprocess.run([p], capture_output=True, text=True).stdout, "shipped\n")
        os.remove(p)


@unittest.skipUnless(have_drive_sil(), "no drive_sil (make build/host/drive_sil)")
class Campaign(unittest.TestCase):
    """Campaigns of a few draws on the paper's motor, short timeline."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_campaign-")
        cls.motor = os.path.join(cls.tmp.name, "motor.ini")
        with open(PAPER) as f:
            text = f.read()
        with open(cls.motor, "w") as f:
            f.write(text + SHORT)
        cls.local = os.path.join(cls.tmp.name, "local")
        cls.first = run_campaign(cls.motor, "--out", cls.local, "--draws", "6", "--jobs", "2")
        cls.rows6 = read_rows(cls.local) if cls.first.returncode == 0 else None
        cls.second = run_campaign(cls.motor, "--out", cls.local, "--draws", "9", "--jobs", "2")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def last_line(self, p):
        self.assertEqual(p.returncode, 0, p.stderr)
        return p.stdout.strip().splitlines()[-1]

    def test_results_report_and_reproducers(self):
        self.assertRegex(self.last_line(self.first), r"^campaign: 6 draws \(6 run now, 0 found\), rule held in \d+ ")
        rows = read_rows(self.local)
        self.assertEqual([r["draw"] for r in rows], list(range(9)))
        for c in ("te_err_conv_Nm", "te_err_prop_Nm", "state_conv", "state_prop", "fault_conv", "fault_prop",
                  "speed_err_conv_rpm", "method_ran_prop", "held_share_prop", "R_err_prop_pct", "psif_err_prop_pct"):
            self.assertIn(c, rows[0])
        self.assertTrue(all(r["state_conv"] and r["state_prop"] for r in rows))
        with open(os.path.join(self.local, "report.md")) as f:
            report = f.read()
        for png in re.findall(r"\]\((\w+\.png)\)", report):
            self.assertTrue(os.path.getsize(os.path.join(self.local, png)) > 1000, png)
        self.assertGreaterEqual(len(re.findall(r"\.png\)", report)), 2)
        self.assertIn("drive_sil ", report)
        self.assertTrue(os.listdir(os.path.join(self.local, "worst")))

    def test_inputs_in_the_results_are_the_draws(self):
        with open(os.path.join(self.local, "campaign.json")) as f:
            ident = json.load(f)
        with open(self.motor) as f:
            text = f.read()
        spec = cs.Spec(self.motor, text, MOTOR)      # the same motor as the file's data
        self.assertEqual(ident["spec"]["window"], "1.18:1.28")   # 0.6 + 0.19 + 0.1 + 0.19 + 0.1
        for r in read_rows(self.local):
            x = spec.inputs(ident["seed"], r["draw"])
            for c in cs.INPUT_COLUMNS + ["noise_seed"]:
                self.assertEqual(r[c], x[c], (r["draw"], c))

    def test_resume_runs_only_the_new_draws(self):
        self.assertRegex(self.last_line(self.second), r"^campaign: 9 draws \(3 run now, 6 found\)")
        rows9 = read_rows(self.local)
        self.assertEqual(rows9[:6], self.rows6)
        p = run_campaign(self.motor, "--out", self.local, "--draws", "4")
        self.assertRegex(self.last_line(p), r"^campaign: 4 draws \(0 run now, 4 found\)")
        self.assertEqual(read_rows(self.local), self.rows6[:4])
        run_campaign(self.motor, "--out", self.local, "--draws", "9")

    def test_another_spec_refused(self):
        before = sorted(os.listdir(self.local))
        p = run_campaign(self.motor, "--out", self.local, "--draws", "9", "--seed", "2")
        self.assertEqual(p.returncode, 2)
        self.assertIn("seed 1 -> 2", p.stderr)
        self.assertIn("--fresh", p.stderr)
        self.assertEqual(sorted(os.listdir(self.local)), before)

    def test_dask_gives_the_same_numbers(self):
        out = os.path.join(self.tmp.name, "dask")
        p = run_campaign(self.motor, "--out", out, "--draws", "9", "--jobs", "2", "--chunk", "2",
                         "--scheduler", "dask-local")
        self.assertRegex(self.last_line(p), r"^campaign: 9 draws \(9 run now, 0 found\)")
        local, dask = read_rows(self.local), read_rows(out)
        self.assertEqual(len(dask), len(local))
        for a, b in zip(local, dask):
            for c in a:
                same = a[c] == b[c] or (isinstance(a[c], float) and math.isnan(a[c]) and math.isnan(b[c]))
                self.assertTrue(same, f"draw {a['draw']} {c}: local {a[c]!r}, dask {b[c]!r}")

    def test_reproducers_rerun_to_their_figure(self):
        rows = {r["draw"]: r for r in read_rows(self.local)}
        worst = os.path.join(self.local, "worst")
        files = sorted(os.listdir(worst))
        self.assertTrue(files)
        for name in files:
            with open(os.path.join(worst, name)) as f:
                text = f.read()
            window = re.search(r"^; win steady = (\S+)$", text, re.M).group(1)
            recorded = re.search(r"^; te_err_Nm = (\S+)$", text, re.M).group(1)
            self.assertNotIn("[campaign]", text)
            p = subprocess.run([DRIVE_SIL, "--scenario", os.path.join(worst, name), "--summary", "-",
                                "--window", window], capture_output=True, text=True)
            self.assertIn(p.returncode, (0, 3), p.stderr)
            self.assertEqual(f"{json.loads(p.stdout)['te_err_Nm']:.9g}", recorded, name)
            draw, m = re.match(r"draw(\d+)_(conv|prop)\.ini", name).groups()
            self.assertEqual(recorded, f"{rows[int(draw)][f'te_err_{m}_Nm']:.9g}")
        # drivekit.rule_check (rule-check), the rule's home, judges the pairs as the results do
        p = subprocess.run([sys.executable, "-m", "drivekit.rule_check", "--drive-sil", DRIVE_SIL, worst],
                           capture_output=True, text=True,
                           env=dict(os.environ, PYTHONPATH=os.path.join(ROOT, "tools", "drivekit")))
        for line in p.stdout.splitlines():
            m = re.match(r"^(ok  |FAIL) draw(\d+) ", line)
            if m:
                self.assertEqual(m.group(1) == "ok  ", rows[int(m.group(2))]["rule_ok"], line)

    def test_interrupt_keeps_the_finished_chunks(self):
        out = os.path.join(self.tmp.name, "interrupted")
        env = dict(ENV, PYTHONPATH=os.path.join(ROOT, "tools", "drivekit"), PYTHONDONTWRITEBYTECODE="1")
        p = subprocess.Popen(campaign_cmd() + ["--drive-sil", DRIVE_SIL, "--quiet", self.motor, "--out", out,
                                               "--draws", "30", "--jobs", "1", "--chunk", "1"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, env=env)
        parts = os.path.join(out, "parts")
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and p.poll() is None and not (
                os.path.isdir(parts) and any(f.endswith(".parquet") for f in os.listdir(parts))):
            time.sleep(0.01)
        p.send_signal(signal.SIGINT)
        _, err = p.communicate(timeout=60)
        if p.returncode == 0:
            self.skipTest("the campaign ended before the interrupt")
        self.assertEqual(p.returncode, 130, err)
        self.assertIn("run it again to resume", err)
        self.assertFalse(os.path.exists(os.path.join(out, "results.parquet")))
        kept = int(re.search(r"interrupted: (\d+) of 30", err).group(1))
        self.assertGreaterEqual(kept, 1)
        q = run_campaign(self.motor, "--out", out, "--draws", "9")
        self.assertRegex(self.last_line(q), rf"^campaign: 9 draws \({9 - min(kept, 9)} run now, {min(kept, 9)} found\)")
        self.assertEqual(read_rows(out), read_rows(self.local))

    def test_bad_input_named_nothing_written(self):
        bad_motor = os.path.join(self.tmp.name, "bad.ini")
        with open(bad_motor, "w") as f:
            f.write("[plant]\nR_ohm = 3\n[controller]\nmethod = proposed\n[identify]\nmode = speeds\n"
                    "[campaign]\nR_factor = uniform 1\n")
        unknown = os.path.join(self.tmp.name, "unknown.ini")
        with open(unknown, "w") as f:
            f.write("[plant]\nR_ohm = 3\n[controller]\nmethod = proposed\n[identify]\nmode = speeds\n"
                    "[campaign]\nspeed = 0.5\n")
        low_bus = os.path.join(self.tmp.name, "low_bus.ini")
        with open(self.motor) as f, open(low_bus, "w") as g:
            g.write(f.read() + "[campaign]\nvdc_factor = choice 0.001 1\n")
        a_file = os.path.join(self.tmp.name, "a_file")
        open(a_file, "w").close()
        out = os.path.join(self.tmp.name, "never")
        cases = [((bad_motor, "--out", out), "bad.ini:8: [campaign] R_factor: uniform takes 2 numbers"),
                 ((unknown, "--out", out), "unknown.ini:8: [campaign] speed: unknown key"),
                 ((self.motor, "--out", out, "--draws", "0"), "--draws 0: expected a whole number >= 1"),
                 ((self.motor, "--out", out, "--draws", "ten"), "--draws 'ten': expected a whole number"),
                 ((self.motor, "--out", os.path.join(a_file, "x")), "cannot be created"),
                 ((self.motor, "--out", a_file), "exists and is no directory"),
                 ((os.path.join(self.tmp.name, "missing.ini"), "--out", out), "missing.ini: no such motor file"),
                 ((self.motor, "--out", out, "--scheduler", "yarn"), "--scheduler yarn"),
                 ((self.motor, "--out", ROOT), "other files and no campaign.json"),
                 ((low_bus, "--out", out), "the distributions' low ends (conventional): drive_sil refuses them: "
                                           "drive_sil: --set plant.vdc_V=0.311: [plant] vdc_V")]
        for args, words in cases:
            p = run_campaign(*args)
            self.assertEqual(p.returncode, 2, (args, p.stderr))
            self.assertIn(words, p.stderr, args)
            self.assertFalse(os.path.exists(out), args)

    def test_make_campaign_out_is_the_campaigns(self):
        p = subprocess.run(["make", "-n", "campaign", f"MOTOR={self.motor}", "OUT=/x/camp", "DRAWS=7", "SEED=3",
                            "SCHEDULER=dask-local"], capture_output=True, text=True, cwd=ROOT, env=ENV)
        self.assertEqual(p.returncode, 0, p.stderr)
        cmd = " ".join(p.stdout.replace("\\\n", " ").split())
        self.assertIn(f"drive-campaign '{self.motor}' --out '/x/camp' --draws '7' --seed '3' --scheduler "
                      "'dask-local' --drive-sil build/host/drive_sil", cmd)
        p = subprocess.run(["make", "-n", "campaign"], capture_output=True, text=True, cwd=ROOT, env=ENV)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("name the motor file", p.stderr)


if __name__ == "__main__":
    unittest.main()

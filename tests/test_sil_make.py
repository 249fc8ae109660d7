#!/usr/bin/env python3
"""tests/test_sil_make.py - the rules of `make sil` (tools/drivekit/module.mk)
with a fake drive_sil and fake venv scripts on a temporary BUILD: a cold run
runs every scenario once and draws every plot in one call; a second run
runs nothing, nor does a relinked drive_sil with the same code (a new
revision string); a run whose CSV is out of date runs again alone, and
only its plot is redrawn; new code in drive_sil runs everything again; exit status 3 (the run
ended in FAULT) is a result, 2 an error that leaves no CSV; SIL_SEEDS
decides the seeds files' lines, and a changed list redoes them. And
`make clean` keeps build/venv, `make distclean` removes all of BUILD."""
import glob
import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENV = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS", "MAKEOVERRIDES")}
STEMS = sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(ROOT, "tools", "scenarios", "*.ini")))
REAL = [s for s in STEMS if s.startswith("real_")]

FAKE_DRIVE_SIL = r'''#!/usr/bin/env bash
# drive_sil --scenario S (--out O | --batch): logs its call; FAKE_EXIT3 / FAKE_EXIT2 name a stem that exits 3 / 2
while [ $# -gt 0 ]; do case $1 in --scenario) s=$2; shift;; --out) o=$2; shift;; --batch) b=1;; esac; shift; done
stem=$(basename "$s" .ini)
echo "run $stem ${b:+batch}" >> "$FAKE_LOG"
if [ -n "${b:-}" ]; then while IFS= read -r line; do echo "{\"id\": \"${line%%	*}\", \"te_err_Nm\": 0.01}"; done; exit 0; fi
[ "$stem" = "${FAKE_EXIT2:-}" ] && { echo "bad input" >&2; exit 2; }
echo "t_s" > "$o"; echo '{}' > "${o%.csv}.resolved.json"
[ "$stem" = "${FAKE_EXIT3:-}" ] && exit 3
exit 0
'''
FAKE_SIL_PLOT = r'''#!/usr/bin/env bash
# the venv's sil-plot: touches a PNG per CSV and logs
csvs=(); while [ $# -gt 0 ]; do case $1 in --jobs) shift;; -*) ;; *) csvs+=("$1");; esac; shift; done
echo "plot ${csvs[*]}" >> "$FAKE_LOG"; for c in "${csvs[@]}"; do touch "${c%.csv}.png"; done
'''
FAKE_SIL_REPORT = r'''#!/usr/bin/env bash
# the venv's sil-report: writes report.md and logs
while [ $# -gt 0 ]; do case $1 in --dir) d=$2; shift;; esac; shift; done
echo "report" >> "$FAKE_LOG"; echo "# report" > "$d/report.md"; exit "${FAKE_REPORT_RC:-0}"
'''


@unittest.skipUnless(shutil.which("make"), "make not installed")
class SilRules(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        t = self._tmp.name
        self.build = os.path.join(t, "build")
        self.sil = os.path.join(self.build, "sil")
        self.log = os.path.join(t, "log")
        self.drive_sil = os.path.join(t, "drive_sil")
        venv_bin = os.path.join(self.build, "venv", "bin")
        os.makedirs(venv_bin)
        for path, text in ((self.drive_sil, FAKE_DRIVE_SIL), (os.path.join(venv_bin, "sil-plot"), FAKE_SIL_PLOT),
                           (os.path.join(venv_bin, "sil-report"), FAKE_SIL_REPORT)):
            with open(path, "w") as f:
                f.write(text)
            os.chmod(path, 0o755)
        for name in (".installed", ".drivekit"):                # a built venv: newer than drivekit's sources
            open(os.path.join(self.build, "venv", name), "w").close()

    def tearDown(self):
        self._tmp.cleanup()

    def make(self, *args, **env):
        open(self.log, "w").close()
        p = subprocess.run(["make", "-C", ROOT, "--no-print-directory", "BUILD=" + self.build,
                            "SIL_PROG=" + self.drive_sil, "SIL_PROG_INPUTS=" + self.drive_sil, *args],
                           env=dict(ENV, FAKE_LOG=self.log, **env), capture_output=True, text=True)
        with open(self.log) as f:
            return p, f.read().splitlines()

    def age(self, path, seconds=1000):
        st = os.stat(path)
        os.utime(path, (st.st_atime - seconds, st.st_mtime - seconds))

    def test_incremental(self):
        p, log = self.make("sil", FAKE_EXIT3=STEMS[0])          # a FAULT run is a result
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        runs = sorted(x for x in log if x.startswith("run ") and not x.endswith("batch"))
        self.assertEqual(runs, sorted("run " + s + " " for s in STEMS))
        self.assertEqual(sorted(x for x in log if x.endswith("batch")), sorted(f"run {s} batch" for s in REAL))
        plots = [x for x in log if x.startswith("plot ")]
        self.assertEqual(len(plots), 1)                          # every plot in one process
        self.assertEqual(sorted(plots[0].split()[1:]), sorted(os.path.join(self.sil, s + ".csv") for s in STEMS))
        self.assertEqual(log[-1], "report")
        for s in STEMS:
            self.assertTrue(os.path.exists(os.path.join(self.sil, s + ".png")), s)
        with open(os.path.join(self.sil, "seeds", REAL[0] + ".jsonl")) as f:
            self.assertEqual([line.split('"')[3] for line in f], [f"seed{k}" for k in range(1, 9)])

        p, log = self.make("sil")                                # nothing changed: nothing runs
        self.assertEqual((p.returncode, log), (0, []), p.stdout + p.stderr)

        for ext in (".csv", ".png"):                              # one run out of date
            self.age(os.path.join(self.sil, STEMS[1] + ext))
        p, log = self.make("sil")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(log, [f"run {STEMS[1]} ", "plot " + os.path.join(self.sil, STEMS[1] + ".csv"), "report"])

        os.remove(os.path.join(self.sil, STEMS[2] + ".png"))      # a plot deleted: drawn again alone
        p, log = self.make("sil")
        self.assertEqual(log, ["plot " + os.path.join(self.sil, STEMS[2] + ".csv")])

        os.utime(self.drive_sil)                                 # drive_sil relinked, same code: nothing
        p, log = self.make("sil")
        self.assertEqual((p.returncode, log), (0, []), p.stdout + p.stderr)

        with open(self.drive_sil, "a") as f:                     # drive_sil's code changed: every run again
            f.write("# changed\n")
        p, log = self.make("-j2", "sil")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(len([x for x in log if x.startswith("run ") and not x.endswith("batch")]), len(STEMS))

        p, log = self.make("sil", "SIL_SEEDS=3 4")               # another seed list: the seeds files again
        self.assertEqual(sorted(x for x in log if x.startswith("run ")), sorted(f"run {s} batch" for s in REAL))
        with open(os.path.join(self.sil, "seeds", REAL[0] + ".jsonl")) as f:
            self.assertEqual([line.split('"')[3] for line in f], ["seed3", "seed4"])

    def test_bad_input_stops_and_leaves_no_csv(self):
        p, log = self.make("sil", FAKE_EXIT2=STEMS[0])
        self.assertNotEqual(p.returncode, 0)
        self.assertFalse(os.path.exists(os.path.join(self.sil, STEMS[0] + ".csv")))
        self.assertFalse(os.path.exists(os.path.join(self.sil, "report.md")))


    def test_failed_report_kept_and_redone(self):
        p, log = self.make("sil", FAKE_REPORT_RC="1")           # a run the report could not measure
        self.assertNotEqual(p.returncode, 0)
        report = os.path.join(self.sil, "report.md")
        self.assertEqual(os.path.getmtime(report), 0)            # kept to be read, out of date
        p, log = self.make("sil")
        self.assertEqual((p.returncode, log), (0, ["report"]), p.stderr)
        self.assertGreater(os.path.getmtime(report), 0)


@unittest.skipUnless(shutil.which("make"), "make not installed")
class Clean(unittest.TestCase):
    def test_clean_keeps_the_venv_distclean_not(self):
        with tempfile.TemporaryDirectory() as t:
            build = os.path.join(t, "build")
            for rel in ("venv/bin/python", "host/drive_sil", "sil/x.csv", ".hidden", "venv2/x"):
                os.makedirs(os.path.dirname(os.path.join(build, rel)), exist_ok=True)
                open(os.path.join(build, rel), "w").close()
            p = subprocess.run(["make", "-C", ROOT, "-s", "BUILD=" + build, "clean"], env=ENV,
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(os.listdir(build), ["venv"])
            self.assertTrue(os.path.exists(os.path.join(build, "venv", "bin", "python")))
            p = subprocess.run(["make", "-C", ROOT, "-s", "BUILD=" + build, "distclean"], env=ENV,
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertFalse(os.path.exists(build))


if __name__ == "__main__":
    unittest.main()

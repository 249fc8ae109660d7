#!/usr/bin/env python3
"""tests/test_make_help.py - `make help` lists every .PHONY target of the
Makefile and its fragments (make's own database is the reference), and
tools/make/make_help.sh --check, the gate of `make check`, fails naming a
.PHONY target that has no "## " description."""
import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "tools", "make", "make_help.sh")
# A make run from `make test` must not see the outer make's flags or jobserver.
ENV = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS", "MAKEOVERRIDES")}


def run(args, **kw):
    return subprocess.run(args, env=ENV, capture_output=True, text=True, **kw)


class Script(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.mk = os.path.join(self._tmp.name, "x.mk")

    def tearDown(self):
        self._tmp.cleanup()

    def write(self, text):
        with open(self.mk, "w") as f:
            f.write(text)

    def test_lists_documented_targets(self):
        self.write(".PHONY: one two\none: dep ## the first\n\t@true\ntwo three: ## two at once\nVAR := x ## no rule\n")
        p = run([SCRIPT, self.mk])
        self.assertEqual(p.returncode, 0, p.stderr)
        rows = [line.split(None, 2) for line in p.stdout.splitlines()]
        self.assertEqual(rows, [["make", "one", "the first"], ["make", "two", "two at once"],
                                ["make", "three", "two at once"]])

    def test_check_fails_naming_the_undocumented(self):
        self.write(".PHONY: one two\n.PHONY: four\none: ## the first\n\t@true\ntwo:\n\t@true\nfour: one\n")
        p = run([SCRIPT, "--check", self.mk])
        self.assertEqual(p.returncode, 1)
        self.assertIn("without a '## ' description", p.stdout)
        self.assertTrue(p.stdout.rstrip().endswith(": four two"), p.stdout)

    def test_check_passes(self):
        self.write(".PHONY: one\none: ## the first\n")
        p = run([SCRIPT, "--check", self.mk])
        self.assertEqual((p.returncode, p.stdout.strip()), (0, "make help: every .PHONY target (1) is described"))


@unittest.skipUnless(shutil.which("make"), "make not installed")
class RealMakefile(unittest.TestCase):
    def test_every_phony_target_listed(self):
        db = run(["make", "-C", ROOT, "--no-print-directory", "-pq", "help"])
        phony = set()
        for line in db.stdout.splitlines():
            if line.startswith(".PHONY:"):
                phony.update(line.split()[1:])
        self.assertIn("sil", phony)
        self.assertIn("clean", phony)
        p = run(["make", "-C", ROOT, "--no-print-directory", "-s", "help"])
        self.assertEqual(p.returncode, 0, p.stderr)
        listed = {line.split()[1] for line in p.stdout.splitlines() if line.startswith("  make ")}
        self.assertEqual(sorted(phony - listed), [])


if __name__ == "__main__":
    unittest.main()

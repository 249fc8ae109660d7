#!/usr/bin/env python3
"""tests/test_commit_subjects.py - tools/check/commit_subjects.sh, the commit
subject gate of `make check`, on throw-away git repositories: it fails
naming the commit whose subject is too long, passes when every subject
after the baseline fits (the baseline's own and older ones are not
judged), and skips when the baseline is not in the history or the
directory is no git checkout."""
import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "tools", "check", "commit_subjects.sh")
ENV = dict(os.environ, GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@example.com",
           GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@example.com",
           GIT_CONFIG_GLOBAL=os.devnull, GIT_CONFIG_NOSYSTEM="1")


@unittest.skipUnless(shutil.which("git"), "git not installed")
class CommitSubjects(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.repo = self._tmp.name
        self.git("init", "-q")

    def tearDown(self):
        self._tmp.cleanup()

    def git(self, *args):
        return subprocess.run(["git", "-C", self.repo, *args], env=ENV, check=True,
                              capture_output=True, text=True).stdout.strip()

    def commit(self, message):
        self.git("commit", "-q", "--allow-empty", "-m", message)
        return self.git("rev-parse", "--short", "HEAD")

    def check(self, base, *extra):
        p = subprocess.run([SCRIPT, base, *extra, self.repo] if extra else [SCRIPT, base, "72", self.repo],
                           env=ENV, capture_output=True, text=True)
        return p.returncode, p.stdout

    def test_long_subject_fails_and_is_named(self):
        base = self.commit("x" * 100)                      # before the baseline: not judged
        self.commit("a" * 72)                              # exactly the limit: fine
        bad = self.commit("b" * 73 + "\n\nbody lines may be as long as they like " + "c" * 100)
        self.commit("short")
        rc, out = self.check(base)
        self.assertEqual(rc, 1, out)
        failing = [line for line in out.splitlines() if line.startswith("FAIL")]
        self.assertEqual(len(failing), 1, out)
        self.assertIn(f"commit {bad}: subject is 73 characters (max 72)", failing[0])
        self.assertIn("1 of 3 commits", out)

    def test_subject_is_the_first_paragraph(self):
        # git joins a first paragraph without a blank line into one subject
        base = self.commit("base")
        bad = self.commit("first line of forty characters, not more\nand a second one, also forty characters")
        rc, out = self.check(base)
        self.assertEqual(rc, 1, out)
        self.assertIn(f"commit {bad}: subject is 80 characters", out)

    def test_short_subjects_pass(self):
        base = self.commit("base")
        self.commit("one")
        self.commit("two")
        rc, out = self.check(base)
        self.assertEqual((rc, out.strip()), (0, f"commit subjects: 2 commits after {base}, every subject <= 72 characters"))

    def test_limit_is_a_parameter(self):
        base = self.commit("base")
        self.commit("twelve chars")
        self.assertEqual(self.check(base, "12", self.repo)[0], 0)
        self.assertEqual(self.check(base, "11", self.repo)[0], 1)

    def test_baseline_not_in_history_skips(self):
        self.commit("y" * 100)
        rc, out = self.check("73c655a")
        self.assertEqual(rc, 0, out)
        self.assertIn("skipped (baseline 73c655a is not in this history", out)

    def test_not_a_checkout_skips(self):
        with tempfile.TemporaryDirectory() as d:
            p = subprocess.run([SCRIPT, "73c655a", "72", d], env=dict(ENV, GIT_CEILING_DIRECTORIES=os.path.dirname(d)),
                               capture_output=True, text=True)
        self.assertEqual((p.returncode, p.stdout.strip()), (0, "commit subjects: skipped (not a git checkout)"))


if __name__ == "__main__":
    unittest.main()

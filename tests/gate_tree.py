"""tests/gate_tree.py - the self-tests of the gates of `make check`
(tools/check/*.sh, which work from the tree they sit in) on throw-away
trees: GateCase copies the gate's script SCRIPT into a temporary tree with
the folders DIRS; a test writes files there and runs the gate."""
import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class GateCase(unittest.TestCase):
    SCRIPT = ""   # the gate: tools/check/SCRIPT
    DIRS = ()     # folders the tree starts with

    def setUp(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        self.root = tmp.name
        self.script = os.path.join(self.root, "tools", "check", self.SCRIPT)
        for d in ("tools/check",) + tuple(self.DIRS):
            os.makedirs(os.path.join(self.root, d), exist_ok=True)
        shutil.copy(os.path.join(ROOT, "tools", "check", self.SCRIPT), self.script)

    def write(self, rel, text):
        """The file rel of the tree, with text."""
        with open(os.path.join(self.root, rel), "w", encoding="utf-8") as f:
            f.write(text)

    def run_gate(self):
        """The gate run in the tree: (exit status, stdout)."""
        p = subprocess.run(["bash", self.script], capture_output=True, text=True)
        return p.returncode, p.stdout

    def assert_gate_fails(self, *texts):
        """The gate exits 1, its output holding each of texts."""
        rc, out = self.run_gate()
        self.assertEqual(rc, 1, out)
        for t in texts:
            self.assertIn(t, out)

#!/usr/bin/env python3
"""tests/test_drivekit.py - the drivekit package as a whole: every module
imports without matplotlib (the checks of `make test` run on the system
python3, and a plot's usage errors come before matplotlib is needed), and
every console script of pyproject.toml names a module's main(), and every
module with a main() has its console script (the others are libraries of
a command, e.g. campaign_spec). Standard library only."""
import os
import re
import subprocess
import sys
import unittest

DRIVEKIT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools", "drivekit")
MODULES = sorted(f[:-3] for f in os.listdir(os.path.join(DRIVEKIT, "drivekit"))
                 if f.endswith(".py") and f != "__init__.py")


def console_scripts():
    """{command: "drivekit.MODULE:main"} of pyproject.toml's [project.scripts]."""
    with open(os.path.join(DRIVEKIT, "pyproject.toml")) as f:
        text = f.read()
    section = re.search(r"(?ms)^\[project\.scripts\]\n(.*?)(?=^\[|\Z)", text).group(1)
    return dict(re.findall(r'(?m)^([\w-]+)\s*=\s*"([^"]+)"', section))


class Package(unittest.TestCase):
    def test_no_module_loads_matplotlib_at_import(self):
        code = ("import importlib, sys; sys.path.insert(0, sys.argv[1]); "
                "[importlib.import_module('drivekit.' + m) for m in sys.argv[2:]]; "
                "print('matplotlib' in sys.modules)")
        p = subprocess.run([sys.executable, "-B", "-c", code, DRIVEKIT, *MODULES], capture_output=True, text=True)
        self.assertEqual((p.returncode, p.stdout.strip()), (0, "False"), p.stderr)

    def test_console_scripts_name_each_modules_main(self):
        scripts = console_scripts()
        self.assertIn("sil-plot", scripts)                        # the name README and `make plot` use
        targets = set(scripts.values())
        self.assertEqual(len(targets), len(scripts))              # one command a module
        sys.path.insert(0, DRIVEKIT)
        import importlib
        commands = {m for m in MODULES if callable(getattr(importlib.import_module("drivekit." + m), "main", None))}
        self.assertEqual(targets, {f"drivekit.{m}:main" for m in commands})


if __name__ == "__main__":
    unittest.main()

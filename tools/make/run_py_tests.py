#!/usr/bin/env python3
"""run_py_tests.py [DIR] - the Python tools' unit tests, DIR/test_*.py
(default tests/), with the standard library's unittest: its report, then
one closing line "tools: N passed, N failed" (an error in a test or an
import counts as failed). Exits non-zero when any test failed or none ran."""
import sys
import unittest


def main(argv):
    d = argv[1] if len(argv) > 1 else "tests"
    suite = unittest.defaultTestLoader.discover(d, pattern="test_*.py", top_level_dir=d)
    res = unittest.TextTestRunner(stream=sys.stdout, verbosity=1).run(suite)
    failed = len(res.failures) + len(res.errors) + len(res.unexpectedSuccesses)
    passed = res.testsRun - failed - len(res.skipped)
    print(f"tools: {passed} passed, {failed} failed")
    return 0 if res.testsRun and not failed else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))

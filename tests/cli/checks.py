"""checks.py - a command-line suite's checks (tests/cli/test_*.py): each
printed "ok   NAME: what" or "FAIL NAME: what", and the closing line
"NAME: N passed, N failed" tools/make/suite.sh counts."""


class Checks:
    def __init__(self, name):
        self.name = name
        self.passed = 0
        self.failed = []

    def __call__(self, ok, what):
        print("%s %s: %s" % ("ok  " if ok else "FAIL", self.name, what))
        if ok:
            self.passed += 1
        else:
            self.failed.append(what)

    def close(self):
        """The closing line; the exit status (1 when a check failed)."""
        print("%s: %d passed, %d failed" % (self.name, self.passed, len(self.failed)))
        return 1 if self.failed else 0

#!/usr/bin/env python3
"""The rule for the proposed method over pairs of scenario files.

    rule-check [--drive-sil BIN] [--set section.key=value ...] DIR|FILE...

Each NAME_prop.ini found (a directory: all of them in it) is run beside its
NAME_conv.ini by drive_sil --summary, in the window its `; win steady = T0:T1`
comment names (else `; win late`, else 0.8:1.2 s). The rule, with the
defaults the files leave unset: the proposed method faults only where the
conventional one does, and its mean |Te - Te*| is at most the conventional
one's + 0.005 N m. Prints one line per pair and `N passed, N failed`; exits
1 when a pair breaks the rule, 2 on bad input.
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys

TE_MARGIN_NM = 0.005          # the rule's allowance over the conventional method
DEFAULT_WINDOW = "0.8:1.2"    # when a file names no window
WINDOW_RE = re.compile(r"^;\s*win\s+(steady|late)\s*=\s*([0-9.eE+-]+:[0-9.eE+-]+)")


def window_of(path):
    """The judged window of a scenario file: steady, else late, else the default."""
    found = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = WINDOW_RE.match(line)
            if m:
                found.setdefault(m.group(1), m.group(2))
    return found.get("steady", found.get("late", DEFAULT_WINDOW))


def summary(drive_sil, path, window, sets):
    """drive_sil's summary of one run (a dict), or one with "error"."""
    cmd = [drive_sil, "--scenario", path, "--summary", "-", "--window", window]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if p.returncode != 0:
        return {"error": (p.stderr or p.stdout).strip()}
    return json.loads(p.stdout)


def judge(conv, prop):
    """(ok, reason) of the rule for one pair of summaries."""
    for name, s in (("conventional", conv), ("proposed", prop)):
        if "error" in s:
            return False, f"{name}: {s['error']}"
    conv_fault = conv["fault_name"] != "NONE"
    prop_fault = prop["fault_name"] != "NONE"
    if prop_fault and not conv_fault:
        return False, f"proposed faults ({prop['fault_name']}), conventional does not"
    if prop_fault or conv_fault:
        return True, "both fault" if prop_fault else "conventional faults"
    if prop["te_err_Nm"] > conv["te_err_Nm"] + TE_MARGIN_NM:
        return False, "proposed worse by more than 0.005 N m"
    return True, ""


def pairs(args):
    """The NAME_prop.ini files named or found in the directories named, sorted."""
    out = []
    for a in args:
        if os.path.isdir(a):
            out += glob.glob(os.path.join(a, "*_prop.ini"))
        elif a.endswith("_prop.ini") and os.path.isfile(a):
            out.append(a)
        else:
            raise ValueError(f"{a}: neither a directory nor a NAME_prop.ini file")
    return sorted(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--drive-sil", default=os.environ.get("DRIVE_SIL", "build/host/drive_sil"))
    ap.add_argument("--set", action="append", default=[], help="override for both runs")
    ap.add_argument("paths", nargs="+")
    a = ap.parse_args(argv)
    try:
        props = pairs(a.paths)
    except ValueError as e:
        print(f"rule_check: {e}", file=sys.stderr)
        return 2
    if not props:
        print("rule_check: no NAME_prop.ini found", file=sys.stderr)
        return 2
    passed = failed = 0
    for prop_path in props:
        conv_path = prop_path[: -len("_prop.ini")] + "_conv.ini"
        name = os.path.basename(prop_path)[: -len("_prop.ini")]
        if not os.path.isfile(conv_path):
            print(f"rule_check: {prop_path}: no {os.path.basename(conv_path)} beside it", file=sys.stderr)
            return 2
        w = window_of(prop_path)
        conv = summary(a.drive_sil, conv_path, w, a.set)
        prop = summary(a.drive_sil, prop_path, w, a.set)
        ok, why = judge(conv, prop)
        passed += ok
        failed += not ok

        def fig(s):
            if "error" in s:
                return "error"
            return s["fault_name"] if s["fault_name"] != "NONE" else f"{s['te_err_Nm']:.4f}"
        print(f"{'ok  ' if ok else 'FAIL'} {name:40s} win {w:10s} conv {fig(conv):>12s} prop {fig(prop):>12s} {why}")
    print(f"rule_check: {passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())

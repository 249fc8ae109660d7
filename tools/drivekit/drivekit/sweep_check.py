#!/usr/bin/env python3
"""sweep_check.py DIR [--tol-Nm 0.005] - the rule of the proposed method over
a sweep's DIR/results.csv (drivekit.sweep, both methods): at every grid point
  1. both methods ran (status ok),
  2. the proposed method is not faulted where the conventional one is not,
  3. its mean |Te - Te*| is <= the conventional method's + tol (where neither
     faulted; a point where only the conventional one faulted passes).
Prints one line per violation and a closing line; exits 1 on any violation,
2 on an unreadable DIR. Standard library only (the regression net of
`make test`, tools/drivekit/module.mk, runs it with the system python3).
"""
import argparse
import csv
import math
import os
import sys



TOL_NM = 0.005               # the rule's margin on mean |Te - Te*|


def faulted(r):
    return r["fault_name"] != "NONE" or r["final_state_name"] == "FAULT"


def grid_points(rows, result_cols):
    """(grid column names, {grid values: {method: row}}) of results.csv's rows."""
    grid_cols = [c for c in rows[0] if c not in result_cols and c not in ("method", "status")]
    points = {}
    for r in rows:
        points.setdefault(tuple(r[c] for c in grid_cols), {})[r["method"]] = r
    return grid_cols, points


def violations(points, tol_Nm):
    """([(grid values, problem)], largest proposed - conventional mean |Te - Te*| where both ran)."""
    bad = []
    worst = -math.inf
    for key, m in sorted(points.items(), key=lambda kv: [float(x) for x in kv[0]]):
        conv, prop = m.get("conventional"), m.get("proposed")
        if conv is None or prop is None or conv["status"] != "ok" or prop["status"] != "ok":
            bad.append((key, "not both methods ran"))
            continue
        if faulted(prop) and not faulted(conv):
            bad.append((key, f"proposed faulted ({prop['fault_name']}), conventional did not"))
            continue
        if faulted(prop) or faulted(conv):
            continue
        d = float(prop["te_err_Nm"]) - float(conv["te_err_Nm"])
        worst = max(worst, d)
        if not d <= tol_Nm:
            bad.append((key, f"proposed mean |Te - Te*| {float(prop['te_err_Nm']):.4f} N m > conventional "
                             f"{float(conv['te_err_Nm']):.4f} N m + {tol_Nm:g}"))
    return bad, worst


def at_text(grid_cols, key):
    return ", ".join(f"{c}={float(v):.4g}" for c, v in zip(grid_cols, key))


def check(path, tol_Nm):
    from . import sweep
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no rows")
    grid_cols, points = grid_points(rows, sweep.RESULT_COLS)
    bad, worst = violations(points, tol_Nm)
    for key, problem in bad:
        print(f"FAIL sweep net {at_text(grid_cols, key)}: {problem}")
    print(f"sweep net: {len(points)} points, {len(bad)} violations; largest proposed - conventional "
          f"mean |Te - Te*| {worst:+.4f} N m (allowed +{tol_Nm:g})")
    print(f"sweep net: {len(points) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--tol-Nm", type=float, default=TOL_NM)
    a = ap.parse_args(argv)
    try:
        return check(os.path.join(a.dir, "results.csv"), a.tol_Nm)
    except (OSError, ValueError, KeyError) as e:
        print(f"sweep_check.py: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""campaign_check.py [DIR] [--drive-sil PATH] [--known FILE] [--tol-Nm 0.005]
- the rule of the proposed method over a campaign: every pair of scenario
files DIR/NAME_prop.ini, DIR/NAME_conv.ini (directly in DIR; default
tests/campaign) runs through drive_sil, and in each judged window
  1. the proposed run is not faulted where the conventional one is not,
  2. its mean |Te - Te*| is <= the conventional one's + tol
     (where neither faulted; sweep_check's rule).
The judged windows are the file's `; win steady = T0:T1` and
`; win late = T0:T1` comments (those of the _prop file), 0.8:1.2 s where
it names none; other `; win` labels are informational and not judged.

Prints one table row per pair and window (both methods' mean |Te - Te*|,
their difference, the proposed run's mean R^, L^, psi_f^ errors over the
window, both fault names), then one line per violation and a closing line
"campaign: N passed, N failed".

--known FILE lists pair names (NAME, one a line, # comments) that are known
to break the rule: they are reported as "known" and do not fail the check;
a known pair that now passes is reported ("fixed: remove it from FILE").
Exit 1 on a violation not in FILE, 2 on bad input (no pairs, a drive_sil
that fails or prints no summary). Standard library only.
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys

from .sweep_check import TOL_NM, faulted  # one home for the rule

JUDGED = ("steady", "late")
DEFAULT_WINDOW = (0.8, 1.2)
WIN_RE = re.compile(r"^;\s*win\s+(\w+)\s*=\s*([-+0-9.eE]+)\s*:\s*([-+0-9.eE]+)\s*$")


def judged_windows(path):
    """[(label, t0, t1)] of the file's judged `; win` comments, else the default."""
    wins = []
    with open(path) as f:
        for line in f:
            m = WIN_RE.match(line.strip())
            if m and m.group(1) in JUDGED:
                wins.append((m.group(1), float(m.group(2)), float(m.group(3))))
    return wins or [("default", *DEFAULT_WINDOW)]


def pairs(d):
    """{NAME: (prop path, conv path)} of the pairs directly in d."""
    out = {}
    for p in sorted(glob.glob(os.path.join(d, "*_prop.ini"))):
        name = os.path.basename(p)[:-len("_prop.ini")]
        c = os.path.join(d, name + "_conv.ini")
        if os.path.isfile(c):
            out[name] = (p, c)
    return out


def run(drive_sil, path, t0, t1):
    """drive_sil's summary (dict) of one run over the window t0:t1."""
    r = subprocess.run([drive_sil, "--scenario", path, "--summary", "-", "--window", f"{t0:g}:{t1:g}"],
                       capture_output=True, text=True)
    if r.returncode != 0 or not r.stdout.strip():
        raise ValueError(f"{path}: drive_sil exit {r.returncode}: {r.stderr.strip()[:200]}")
    return json.loads(r.stdout)


def read_known(path):
    if not path:
        return set()
    with open(path) as f:
        return {ln.split("#")[0].strip() for ln in f} - {""}


def fmt(s, key, spec):
    v = s.get(key)
    return format(v, spec) if isinstance(v, (int, float)) else "-"


def check(d, drive_sil, tol_Nm, known):
    ps = pairs(d)
    if not ps:
        raise ValueError(f"{d}: no NAME_prop.ini / NAME_conv.ini pairs")
    print(f"{'pair':44s} {'window':16s} {'conv':>7s} {'prop':>7s} {'diff':>8s}  "
          f"{'R^%':>6s} {'L^%':>6s} {'psif^%':>7s}  faults (conv/prop)")
    failing = {}
    for name, (p, c) in ps.items():
        for label, t0, t1 in judged_windows(p):
            sp, sc = run(drive_sil, p, t0, t1), run(drive_sil, c, t0, t1)
            problem = None
            diff = None
            if faulted(sp) and not faulted(sc):
                problem = f"proposed faulted ({sp['fault_name']}), conventional did not"
            elif not (faulted(sp) or faulted(sc)):
                diff = sp["te_err_Nm"] - sc["te_err_Nm"]
                if not diff <= tol_Nm:
                    problem = (f"proposed mean |Te - Te*| {sp['te_err_Nm']:.4f} N m > conventional "
                               f"{sc['te_err_Nm']:.4f} N m + {tol_Nm:g}")
            dtext = f"{diff:+8.4f}" if diff is not None else f"{'-':>8s}"
            print(f"{name:44s} {label + ' ' + f'{t0:g}:{t1:g}':16s} {fmt(sc, 'te_err_Nm', '7.4f')} "
                  f"{fmt(sp, 'te_err_Nm', '7.4f')} {dtext}  {fmt(sp, 'R_err_pct', '+6.1f')} "
                  f"{fmt(sp, 'L_err_pct', '+6.1f')} {fmt(sp, 'psif_err_pct', '+7.1f')}  "
                  f"{sc['fault_name']}/{sp['fault_name']}{' ' + sp['warning'] if sp.get('warning') else ''}")
            if problem:
                failing.setdefault(name, []).append(f"{label} {t0:g}:{t1:g}: {problem}")
    new = 0
    for name, probs in failing.items():
        tag = "known" if name in known else "FAIL"
        new += tag == "FAIL"
        for pr in probs:
            print(f"{tag} campaign {name} {pr}")
    for name in sorted(known - set(failing)):
        if name in ps:
            print(f"fixed campaign {name}: passes now, remove it from the known list")
    n_fail = len(failing)
    print(f"campaign: {len(ps)} pairs, {n_fail} break the rule ({n_fail - new} known, {new} new)")
    print(f"campaign: {len(ps) - n_fail} passed, {new} failed ({n_fail - new} known failures not counted)")
    return 1 if new else 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", nargs="?", default=os.path.join("tests", "campaign"))
    ap.add_argument("--drive-sil", default=os.path.join("build", "host", "drive_sil"))
    ap.add_argument("--known", default=None)
    ap.add_argument("--tol-Nm", type=float, default=TOL_NM)
    a = ap.parse_args(argv)
    try:
        return check(a.dir, a.drive_sil, a.tol_Nm, read_known(a.known))
    except (OSError, ValueError, KeyError, json.JSONDecodeError) as e:
        print(f"campaign_check.py: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

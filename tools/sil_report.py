#!/usr/bin/env python3
"""sil_report.py - build/sil/report.md: one table row of tools/metrics.py
figures for every scenario CSV in the SIL output directory, with links to
the plots that sit beside it (<stem>*.png / *.svg).

Windows: a run that reaches 0.95 s is measured over 0.8..0.95 s (steady,
before the paper's load step) and its speed recovery over 0.95..1.05 s; a
shorter run over its last quarter.

Usage: sil_report.py [--dir build/sil] [--out build/sil/report.md]
"""
import argparse
import glob
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import metrics  # noqa: E402

PAPER_WINDOW = (0.8, 0.95)
LOAD_WINDOW = (0.95, 1.05)
SHORT_RUN_TAIL = 0.25


def windows(csv_path):
    col = metrics.load_csv(csv_path)
    t_end = col["t_s"][-1]
    if t_end >= LOAD_WINDOW[1]:
        return PAPER_WINDOW, LOAD_WINDOW
    return ((1.0 - SHORT_RUN_TAIL) * t_end, t_end + 1e-9), None


def cell(v, spec):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, spec)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", default="build/sil")
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    out = a.out or os.path.join(a.dir, "report.md")
    csvs = sorted(glob.glob(os.path.join(a.dir, "*.csv")))
    if not csvs:
        print(f"sil_report.py: no CSV in {a.dir}", file=sys.stderr)
        return 1

    lines = [
        "# SIL report",
        "",
        "True plant values against the controller's references (tools/metrics.py).",
        "Steady window 0.8-0.95 s for the 1.2 s runs (last quarter for shorter ones);",
        "recovery: time after the 4 -> 6 N m step at 0.95 s until the speed stays within 1 r/min.",
        "Torque step: periods from the ISR that took the command to 95 % of the step.",
        "",
        "| scenario | mean abs(Te-Te*) [N m] | Te ripple RMS [N m] | mean abs(psi-psi*) [mWb] | psi err [%] "
        "| speed err [r/min] | max abs speed err [r/min] | id [A] | iq [A] | recovery [ms] "
        "| step 95 % [periods] | overshoot [%] | settle 2 % [periods] | plots |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    failed = 0
    for path in csvs:
        stem = os.path.splitext(os.path.basename(path))[0]
        try:
            win, load_win = windows(path)
            r = metrics.compute(path, win, load_win)
        except (OSError, ValueError, KeyError) as e:
            lines.append(f"| {stem} | error: {e} |" + " |" * 12)
            failed += 1
            continue
        plots = sorted(glob.glob(os.path.join(a.dir, stem + "*.png")) + glob.glob(os.path.join(a.dir, stem + "*.svg")))
        links = " ".join(f"[{os.path.basename(p)}]({os.path.basename(p)})" for p in plots) or "-"
        psi_mwb = r["psi_err_Wb"] * 1e3 if math.isfinite(r["psi_err_Wb"]) else math.nan
        lines.append(
            f"| {stem} | {cell(r['te_err_Nm'], '.4f')} | {cell(r['te_ripple_Nm'], '.4f')} "
            f"| {cell(psi_mwb, '.2f')} | {cell(r['psi_err_pct'], '.3f')} "
            f"| {cell(r['speed_err_rpm'], '+.3f')} | {cell(r['speed_err_max_rpm'], '.3f')} "
            f"| {cell(r['id_A'], '+.4f')} | {cell(r['iq_A'], '.4f')} | {cell(r.get('recovery_ms'), '.1f')} "
            f"| {cell(r.get('step_periods_95'), 'd')} | {cell(r.get('step_overshoot_pct'), '.2f')} "
            f"| {cell(r.get('step_settle_periods'), 'd')} | {links} |")
    lines.append("")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "w") as f:
        f.write("\n".join(lines))
    print(f"sil_report.py: {out} ({len(csvs)} scenarios{', %d failed' % failed if failed else ''})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""sil_report.py - build/sil/report.md from the CSVs of `make sil`:

  1. one row of drivekit.metrics figures per scenario CSV, with links to
     the plot drawn for exactly that scenario (<stem>.png / <stem>.svg),
     in two tables (errors and plots; currents, load and torque step);
  2. two tables case x method: every case that has both conv_<case>.csv
     and prop_<case>.csv (torque and flux error, ripple, speed dip at the
     load step; R^/L^/psi_f^ error and time to 2 %, torque-step response),
     with the realistic board's torque error beside the ideal one
     (real_conv_<case>.csv, real_prop_<case>.csv: ADC noise, dead time
     compensated 10 % short, device drop, 1000-line encoder, a warming
     winding; the proposed method's as a fraction of the conventional's);
  3. the realistic runs over noise seeds (seeds/<stem>.jsonl, drive_sil
     --batch lines with plant.seed = 1..8, written by `make sil`): least,
     median and largest torque error per scenario, and the seed of the
     largest (the realistic column is one seed's figure);
  4. figures in the paper's layout (needs matplotlib; skipped without):
     <case>_compare.png  flux ref/response, torque ref/response, psi_f^, L^
                         over time, conventional | proposed side by side;
     prop_<case>_step1.png  i_q, f^_q and R^ during step 1 (like Fig. 3).

True parameters for the estimates' errors come from the run itself: the
resolved values drive_sil writes beside each CSV (<stem>.resolved.json, "plant":
R_ohm, L_H, psif_Wb; --set overrides included).

Windows: a run that reaches 1.05 s is measured over 0.8..0.95 s (steady,
before the paper's load step) and its speed recovery and dip over
0.95..1.05 s; a shorter run over its last quarter; a run of 2.5 s or more
(the motor scenarios: step 1 in speeds mode ends near 0.94 s) over its
last 0.5 s, with no load window.

Figures are drawn only when older than their runs' CSV and resolved
values or than this script (--figures all / none), in --jobs processes.
The realistic / conventional ratio has two significant digits.

Usage: sil_report.py [--dir build/sil] [--out build/sil/report.md] [--jobs N] [--figures stale|all|none]
(--scenarios DIR is still accepted and ignored: the truth is in <stem>.resolved.json.)
"""
import argparse
import glob
import json
import math
import os
import statistics
import sys

from . import metrics

PAPER_WINDOW = (0.8, 0.95)
LOAD_WINDOW = (0.95, 1.05)
SHORT_RUN_TAIL = 0.25
LONG_RUN_S = 2.5          # a run this long is judged over its last LONG_RUN_TAIL_S
LONG_RUN_TAIL_S = 0.5
MOTOR_PREFIX = "motor_"   # case motor_<name>: that motor's scenario; any other: the paper's
METHODS = (("conv", "conventional"), ("prop", "proposed"))
STEP1_TAIL_S = 0.05       # the step-1 figure runs this far past step 2's start
FIG_DPI = 110
# The figures use fixed margins: tight_layout() would lay them out twice.


def windows(col):
    t_end = col["t_s"][-1]
    if t_end >= LONG_RUN_S:
        return (t_end - LONG_RUN_TAIL_S, t_end + 1e-9), None
    if t_end >= LOAD_WINDOW[1]:
        return PAPER_WINDOW, LOAD_WINDOW
    return ((1.0 - SHORT_RUN_TAIL) * t_end, t_end + 1e-9), None


def truth_of(run_dir, stem):
    """(R, L, psif) of the plant of run <stem>: the resolved values drive_sil
    wrote beside its CSV (<run_dir>/<stem>.resolved.json; R at t = 0: the CSV's R_ohm
    column has the rest of a warming winding)."""
    path = os.path.join(run_dir, stem + ".resolved.json")
    try:
        with open(path) as f:
            plant = json.load(f)["plant"]
        return float(plant["R_ohm"]), float(plant["L_H"]), float(plant["psif_Wb"])
    except OSError as e:
        raise ValueError(f"{path}: no resolved values ({e.strerror}); run drive_sil --out {stem}.csv") from None
    except (ValueError, KeyError, TypeError) as e:
        raise ValueError(f"{path}: not drive_sil's resolved values ({e})") from None


def cell(v, spec):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, spec)


def plot_links(d, stem):
    """Links to the plots of exactly this scenario (not of others sharing its prefix)."""
    names = [stem + ".png", stem + ".svg", stem + "_step1.png"]
    return " ".join(f"[{n}]({n})" for n in names if os.path.exists(os.path.join(d, n))) or "-"


def pair_cases(results):
    """[(case, {"conv": r, "prop": r})] for every case with both conv_<case> and
    prop_<case> measured without error, sorted by case name."""
    names = sorted({s.split("_", 1)[1] for s in results if s.startswith(tuple(t + "_" for t, _ in METHODS))})
    cases = []
    for case in names:
        by_method = {tag: results.get(f"{tag}_{case}") for tag, _ in METHODS}
        if all(r is not None and "error" not in r for r in by_method.values()):
            cases.append((case, by_method))
    return cases


def sig(v, digits=2):
    """v in fixed notation with `digits` significant digits (0.0044, 0.25,
    1.2, 12): a ratio far below 1 keeps its figures instead of '0.00'."""
    if v is None or not math.isfinite(v):
        return "-"
    if v == 0:
        return "0"
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(v))))
    text = format(v, f".{decimals}f")
    # rounding may carry into one more digit (0.0995 -> 0.100): drop the extra decimal
    if decimals > 0 and len(text.replace("-", "").replace(".", "").lstrip("0")) > digits:
        text = format(v, f".{decimals - 1}f")
    return text


def error_row(stem, message, width):
    msg = str(message).replace("|", "\\|").replace("\n", " ")
    return f"| {stem} | error: {msg} |" + " |" * (width - 2)


def scenario_table(runs, d):
    """Every scenario's errors against its references, and its plots."""
    lines = [
        "| scenario | mean abs(Te-Te*) [N m] | Te ripple RMS [N m] | mean abs(psi-psi*) [mWb] | psi err [%] "
        "| speed err [r/min] | max abs speed err [r/min] | plots |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for stem, r in runs:
        if "error" in r:
            lines.append(error_row(stem, r["error"], 8))
            continue
        psi_mwb = r["psi_err_Wb"] * 1e3 if math.isfinite(r["psi_err_Wb"]) else math.nan
        lines.append(
            f"| {stem} | {cell(r['te_err_Nm'], '.4f')} | {cell(r['te_ripple_Nm'], '.4f')} "
            f"| {cell(psi_mwb, '.2f')} | {cell(r['psi_err_pct'], '.3f')} "
            f"| {cell(r['speed_err_rpm'], '+.3f')} | {cell(r['speed_err_max_rpm'], '.3f')} "
            f"| {plot_links(d, stem)} |")
    return lines


def scenario_response_table(runs):
    """Every scenario's currents, load-step recovery and torque-step response
    (the runs that failed are named in the first table)."""
    lines = [
        "| scenario | id [A] | iq [A] | recovery [ms] | dip [r/min] "
        "| step 95 % [periods] | overshoot [%] | settle 2 % [periods] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for stem, r in runs:
        if "error" in r:
            continue
        lines.append(
            f"| {stem} | {cell(r['id_A'], '+.4f')} | {cell(r['iq_A'], '.4f')} | {cell(r.get('recovery_ms'), '.1f')} "
            f"| {cell(r.get('speed_dip_rpm'), '.2f')} "
            f"| {cell(r.get('step_periods_95'), 'd')} | {cell(r.get('step_overshoot_pct'), '.2f')} "
            f"| {cell(r.get('step_settle_periods'), 'd')} |")
    return lines


def real_te(real, case, tag):
    """Mean |Te - Te*| of real_<tag>_<case> (None when absent or failed)."""
    r = (real or {}).get(f"real_{tag}_{case}")
    return None if r is None or "error" in r else r.get("te_err_Nm")


def case_rows(cases):
    """(case, method name, result) of every measured run of the cases."""
    for case, by_method in cases:
        for tag, name in METHODS:
            r = by_method.get(tag)
            if r is not None and "error" not in r:
                yield case, tag, name, r


def motor_of(case):
    """The motor of a case: motor_<name> and motor_<name>_<timeline> are that
    motor's, any other the paper's."""
    return case[len(MOTOR_PREFIX):].split("_")[0] if case.startswith(MOTOR_PREFIX) else "paper"


def case_table(cases, d, real=None):
    """Torque and flux per case and method; real: the results by stem, where
    real_<tag>_<case> gives the realistic columns."""
    lines = [
        "| case | method | mean abs(Te-Te*) [N m] | realistic mean abs(Te-Te*) [N m] | realistic / conventional "
        "| psi err [%] | Te ripple RMS [N m] | speed dip [r/min] | figure | motor |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for case, tag, name, r in case_rows(cases):
        fig = f"{case}_compare.png"
        link = f"[{fig}]({fig})" if os.path.exists(os.path.join(d, fig)) else "-"
        conv_real = real_te(real, case, "conv")
        te_real = real_te(real, case, tag)
        ratio = (te_real / conv_real if tag != "conv" and te_real is not None and conv_real
                 else None)
        lines.append(
            f"| {case} | {name} | {cell(r['te_err_Nm'], '.4f')} | {cell(te_real, '.4f')} "
            f"| {sig(ratio)} | {cell(r['psi_err_pct'], '.3f')} "
            f"| {cell(r['te_ripple_Nm'], '.4f')} | {cell(r.get('speed_dip_rpm'), '.2f')} | {link} | {motor_of(case)} |")
    return lines


def estimate_table(cases):
    """The estimates' errors and convergence, and the torque-step response,
    per case and method."""
    lines = [
        "| case | method | R^ err [%] | L^ err [%] | psi_f^ err [%] | L^ in 2 % [ms] | psi_f^ in 2 % [ms] "
        "| step 95 % [periods] | overshoot [%] | motor |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for case, tag, name, r in case_rows(cases):
        lines.append(
            f"| {case} | {name} | {cell(r.get('R_err_pct'), '+.3f')} | {cell(r.get('L_err_pct'), '+.3f')} "
            f"| {cell(r.get('psif_err_pct'), '+.3f')} | {cell(r.get('t2_L_ms'), '.1f')} "
            f"| {cell(r.get('t2_psif_ms'), '.1f')} | {cell(r.get('step_periods_95'), 'd')} "
            f"| {cell(r.get('step_overshoot_pct'), '.2f')} | {motor_of(case)} |")
    return lines


# ---- figures (matplotlib optional) ----------------------------------------

def seed_runs(path):
    """[(id, te_err_Nm or None)] of one seeds/<stem>.jsonl: drive_sil --batch
    lines; a line with an error, no figure or a non-finite one gives None."""
    runs = []
    with open(path) as f:
        for line in f:
            if not line.strip():
                continue
            try:
                r = json.loads(line)
            except ValueError:
                r = None
            if not isinstance(r, dict):
                runs.append(("?", None))
                continue
            v = r.get("te_err_Nm")
            ok = isinstance(v, (int, float)) and math.isfinite(v)
            runs.append((str(r.get("id", "?")), float(v) if ok else None))
    return runs


def seed_table(d):
    """Rows of the realistic runs over noise seeds (<d>/seeds/*.jsonl); [] when none."""
    paths = sorted(glob.glob(os.path.join(d, "seeds", "*.jsonl")))
    if not paths:
        return []
    lines = [
        "| scenario | seeds | least [N m] | median [N m] | largest [N m] | largest at | failed |",
        "|---|---|---|---|---|---|---|",
    ]
    for path in paths:
        stem = os.path.splitext(os.path.basename(path))[0]
        runs = seed_runs(path)
        ok = [(v, ident) for ident, v in runs if v is not None]
        failed = [ident for ident, v in runs if v is None]
        if ok:
            least, median = min(v for v, _ in ok), statistics.median(v for v, _ in ok)
            largest, at = max(ok)
        else:
            least = median = largest = None
            at = "-"
        lines.append(f"| {stem} | {len(runs)} | {cell(least, '.4f')} | {cell(median, '.4f')} "
                     f"| {cell(largest, '.4f')} | {at} | {' '.join(failed) or '-'} |")
    return lines


def compare_figure(plt, case, cols, truth, out):
    """Paper layout: rows flux, torque, psi_f^, L^; columns conventional | proposed."""
    rows = [("stator flux [Wb]", [("psi_ref_Wb", "ref", "--"), ("psi_Wb", "true", "-")], None),
            ("torque [N m]", [("te_ref_Nm", "ref", "--"), ("te_Nm", "true", "-")], None),
            ("psi_f^ [Wb]", [("psif_est_Wb", "estimate", "-")], 2),
            ("L^ [mH]", [("L_est_H", "estimate", "-")], 1)]
    fig, axes = plt.subplots(len(rows), 2, sharex=True, figsize=(12, 10))
    for j, (tag, name) in enumerate(METHODS):
        col = cols.get(tag)
        for i, (ylabel, series, true_idx) in enumerate(rows):
            ax = axes[i][j]
            if col is None:
                continue
            k = 1e3 if ylabel.startswith("L^") else 1.0
            for c, label, style in series:
                if c in col:
                    ax.plot(col["t_s"], [v * k for v in col[c]], style, label=label, linewidth=0.8)
            if true_idx is not None and truth.get(tag) is not None:
                ax.axhline(truth[tag][true_idx] * k, color="k", linestyle=":", linewidth=0.8, label="plant")
            ax.set_ylabel(ylabel)
            ax.grid(True, alpha=0.3)
            ax.legend(loc="best", fontsize="small")
            if i == 0:
                ax.set_title(name)
    for j in range(2):
        axes[-1][j].set_xlabel("t [s]")
    fig.suptitle(f"case {case}: conventional vs proposed")
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.06, top=0.92, wspace=0.2, hspace=0.12)
    fig.savefig(out, dpi=FIG_DPI)
    plt.close(fig)


def step1_figure(plt, stem, col, truth, out):
    """i_q, f^_q and R^ during step 1 (Fig. 3 layout)."""
    ts2 = metrics.step2_start(col)
    if ts2 is None:
        return False
    idx = [i for i, t in enumerate(col["t_s"]) if t <= ts2 + STEP1_TAIL_S]
    t = [col["t_s"][i] for i in idx]
    panels = [("i_q [A]", "iq_A", None), ("f^_q [V]", "fq_est", None), ("R^ [ohm]", "R_est_ohm", truth[0])]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(8, 7))
    for ax, (ylabel, c, ref) in zip(axes, panels):
        ax.plot(t, [col[c][i] for i in idx], linewidth=0.8)
        if ref is not None:
            ax.axhline(ref, color="k", linestyle=":", linewidth=0.8, label="plant")
            ax.legend(loc="best", fontsize="small")
        ax.axvline(ts2, color="r", linestyle="--", linewidth=0.8)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("t [s] (dashed: step 2 starts)")
    fig.suptitle(f"{stem}: step 1 (offline R identification)")
    fig.subplots_adjust(left=0.14, right=0.97, bottom=0.08, top=0.93, hspace=0.12)
    fig.savefig(out, dpi=FIG_DPI)
    plt.close(fig)
    return True


def load_matplotlib():
    try:
        import matplotlib
        matplotlib.use("Agg")
        matplotlib.rcParams["axes.formatter.useoffset"] = False
        import matplotlib.pyplot as plt
        return plt
    except ImportError:
        return None


def stale(out, inputs):
    """True when the figure out is missing or older than any of its inputs
    (the run's CSV and resolved values, this script, metrics.py)."""
    try:
        t_out = os.path.getmtime(out)
    except OSError:
        return True
    code = [os.path.abspath(__file__), os.path.abspath(metrics.__file__)]
    return any(os.path.getmtime(p) > t_out for p in list(inputs) + code if os.path.exists(p))


_FIGURES = []   # [(function, args)] of draw_figures(), inherited by its worker processes
_PLT = None


def _draw(i):
    fn, args = _FIGURES[i]
    fn(_PLT, *args)


def draw_figures(figures, jobs):
    """Draws [(function, args)] as function(plt, *args), in `jobs` processes;
    False when matplotlib is not available."""
    global _FIGURES, _PLT
    if not figures:
        return True
    _PLT = load_matplotlib()
    if _PLT is None:
        return False
    _FIGURES = figures
    n = min(jobs, len(figures))
    if n > 1:
        import multiprocessing
        with multiprocessing.get_context("fork").Pool(n) as pool:
            pool.map(_draw, range(len(figures)), chunksize=1)
    else:
        for i in range(len(figures)):
            _draw(i)
    return True


PREAMBLE = [
    "# SIL report",
    "",
    "True plant values against the controller's references (drivekit.metrics).",
    "Steady window 0.8-0.95 s for the 1.2 s runs (last quarter for shorter ones, the last 0.5 s for runs of 2.5 s "
    "or more: the motor_* cases, each motor told only its data, motor column);",
    "the motor_*_timeline cases: the paper's timeline in per unit of each motor's ratings",
    "(drivekit.motor_timeline: 0.25 n_rated, 1/3 -> 2/3 -> 1 -> 2/3 T_rated).",
    "Recovery and dip: after the 4 -> 6 N m step at 0.95 s (2/3 -> 1 T_rated), until the speed stays within 1 r/min,",
    "and the largest shortfall below the reference until 1.05 s.",
    "Torque step: periods from the ISR that took the command to 95 % of the step.",
    "",
    "## Case x method",
    "",
    "Estimates: mean relative error over the steady window against the plant's values (for the",
    "conventional method the controller's fixed values, i.e. the mismatch); time from the start of",
    "step 2 until the estimate stays within 2 % up to the window's end.",
    "Realistic: the same case on a realistic board (real_<method>_<case>.ini: ADC noise 0.02 A,",
    "dead time 1 us compensated as 0.9 us, device drop 1.2 V, 1000-line encoder, winding warming",
    "3.0 -> 3.9 ohm over the run); the proposed method's error as a fraction of the conventional's.",
    "",
]


def measure(d, csvs):
    """Each run's figures ([(stem, figures or {"error"})]), columns and true
    values by stem, and how many could not be measured (each named)."""
    runs, cols, truths = [], {}, {}
    failed = 0
    for path in csvs:
        stem = os.path.splitext(os.path.basename(path))[0]
        try:
            col = metrics.load_csv(path)
            win, load_win = windows(col)
            truths[stem] = truth_of(d, stem)
            r = metrics.compute(path, win, load_win, truth=truths[stem])
            cols[stem] = col
        except (OSError, ValueError, KeyError) as e:
            r = {"error": str(e)}
            failed += 1
            print(f"sil_report.py: {stem}: {e}", file=sys.stderr)
        runs.append((stem, r))
    return runs, cols, truths, failed


def figure_jobs(d, which, cols, truths, cases):
    """[(function, args)] of the step-1 and comparison figures to draw:
    which is "all", "stale" (older than their runs) or "none"."""
    def wanted(png, *stems):
        inputs = [os.path.join(d, s + ext) for s in stems for ext in (".csv", ".resolved.json")]
        return which == "all" or which == "stale" and stale(png, inputs)

    figures = []
    for stem, col in cols.items():
        png = os.path.join(d, stem + "_step1.png")
        if stem.startswith("prop_") and metrics.step2_start(col) is not None and wanted(png, stem):
            figures.append((step1_figure, (stem, col, truths[stem], png)))
    for case, _ in cases:
        png = os.path.join(d, f"{case}_compare.png")
        if wanted(png, *(f"{tag}_{case}" for tag, _ in METHODS)):
            figures.append((compare_figure, (case, {tag: cols[f"{tag}_{case}"] for tag, _ in METHODS},
                                             {tag: truths[f"{tag}_{case}"] for tag, _ in METHODS}, png)))
    return figures


def report_lines(d, runs, cases, have_plt):
    """report.md's lines: the preamble, the case tables, the seeds' spread,
    every scenario."""
    lines = list(PREAMBLE)
    if cases:
        lines += case_table(cases, d, dict(runs))
        lines += ["", "### Estimates and torque step", ""] + estimate_table(cases)
    else:
        lines.append("(no case with both conv_ and prop_ runs)")
    seeds = seed_table(d)
    if seeds:
        lines += [
            "", "## Realistic board over noise seeds", "",
            "The realistic column above is one noise seed's run (plant.seed = 1). The same scenarios",
            "with other seeds (ADC noise; seeds/<scenario>.jsonl): mean abs(Te-Te*) over the window.",
            "",
        ] + seeds
    lines += ["", "## Every scenario", ""]
    lines += scenario_table(runs, d)
    lines += ["", "### Currents, load step and torque step", ""] + scenario_response_table(runs)
    if not have_plt:
        lines += ["", "(matplotlib not available: comparison and step-1 figures not drawn)"]
    lines.append("")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", default="build/sil")
    ap.add_argument("--scenarios", default=None, help="ignored (old command lines): the truth is in <stem>.resolved.json")
    ap.add_argument("--out", default=None)
    ap.add_argument("--jobs", type=int, default=1, help="processes drawing the figures (default 1)")
    ap.add_argument("--figures", choices=("stale", "all", "none"), default="stale",
                    help="draw the figures older than their runs (default), all, or none")
    a = ap.parse_args(argv)
    out = a.out or os.path.join(a.dir, "report.md")
    csvs = sorted(glob.glob(os.path.join(a.dir, "*.csv")))
    if not csvs:
        print(f"sil_report.py: no CSV in {a.dir}", file=sys.stderr)
        return 1
    runs, cols, truths, failed = measure(a.dir, csvs)
    cases = pair_cases(dict(runs))
    have_plt = draw_figures(figure_jobs(a.dir, a.figures, cols, truths, cases), a.jobs)
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "w") as f:
        f.write("\n".join(report_lines(a.dir, runs, cases, have_plt)))
    print(f"sil_report.py: {out} ({len(csvs)} scenarios, {len(cases)} cases"
          f"{', %d failed' % failed if failed else ''})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""sil_plot.py - plot drive_sil traces with the paper's panels: speed,
torque (ref/true/est), stator flux (ref/true/est), id/iq, ud/uq, and the
controller's estimates R^, L^, psi_f^ and f^ on axes of their own, each
with its unit (the plant's value dashed where the run records it). NaN
columns (no value in the run's mode) draw nothing.

  sil_plot.py RUN.csv                 writes RUN.png beside it
  sil_plot.py RUN.csv -o OUT.png      writes OUT.png (.svg, .pdf by suffix)
  sil_plot.py --jobs 2 A.csv B.csv    A.png and B.png, drawn by 2 processes

The title is the effective scenario from <stem>.resolved.json, which
drive_sil writes beside the CSV (the CSV's name without it): the
scenario's name, the --set overrides on top of it, and what ran (method
and mode, or the commissioning). No axis zooms below a meaningful
resolution: each panel spans at least SPAN_REL of its largest value and
its own floor in its unit, so a constant estimate is a flat line with
plain tick labels, not float32 rounding. Only
files are written, never a window (matplotlib's Agg backend). Needs
matplotlib: `make plot CSV=RUN.csv` or build/venv/bin/sil-plot RUN.csv
use the venv that `make sil` builds. Exit status 0, or 1 when a plot
failed (each failure named), 2 on a bad command line."""
import argparse
import json
import math
import os
import sys
import textwrap

from . import metrics

FIG_SIZE_IN = (10, 17)
DPI = 110
# Fixed margins (fractions of the figure) instead of tight_layout(), which
# lays every axis out once more and costs a third of a plot's time; the
# legends stand right of their axes (never over a trace, and no search
# for the "best" place).
LAYOUT = dict(left=0.09, right=0.85, bottom=0.035, top=0.965, hspace=0.12)
L_DISPLAY_PER_H = 1e3   # L^ drawn in mH
SPAN_REL = 0.01         # a panel spans at least 1 % of its largest |value|
TITLE_WIDTH = 90        # characters a title line holds at FIG_SIZE_IN
TITLE_LINE = 0.016      # the top margin a further title line takes (figure fraction)

# (y label with unit, [(column, legend, style)], [(plant column, legend)], scale,
#  the smallest span drawn, in the panel's unit: its resolution near zero)
PANELS = [
    ("speed [r/min]", [("speed_ref_rpm", "ref", "--"), ("speed_rpm", "true", "-"), ("speed_est_rpm", "est", ":")],
     [], 1.0, 1.0),
    ("torque [N m]", [("te_ref_Nm", "ref", "--"), ("te_Nm", "true", "-"), ("te_est_Nm", "est", ":"),
                      ("load_Nm", "load", "-.")], [], 1.0, 0.01),
    ("stator flux [Wb]", [("psi_ref_Wb", "ref", "--"), ("psi_Wb", "true", "-"), ("psi_est_Wb", "est", ":")],
     [], 1.0, 0.001),
    ("current [A]", [("id_A", "id", "-"), ("iq_A", "iq", "-")], [], 1.0, 0.01),
    ("voltage [V]", [("ud_V", "ud applied", "-"), ("uq_V", "uq applied", "-"),
                     ("ud_cmd_V", "ud cmd", ":"), ("uq_cmd_V", "uq cmd", ":")], [], 1.0, 0.1),
    ("R^ [ohm]", [("R_est_ohm", "R^", "-")], [("R_ohm", "plant")], 1.0, 0.001),
    ("L^ [mH]", [("L_est_H", "L^", "-")], [("L_H", "plant")], L_DISPLAY_PER_H, 0.001),
    ("psi_f^ [Wb]", [("psif_est_Wb", "psi_f^", "-")], [("psif_Wb", "plant")], 1.0, 0.0001),
    ("f^ [V]", [("fd_est", "f^_d", "-"), ("fq_est", "f^_q", "-")], [], 1.0, 0.01),
]


class PlotError(Exception):
    pass


def default_out(csv_path):
    """RUN.csv -> RUN.png; a name without .csv gets .png appended."""
    root, ext = os.path.splitext(csv_path)
    return (root if ext.lower() == ".csv" else csv_path) + ".png"


def resolved_of(csv_path):
    """drive_sil's <stem>.resolved.json beside the CSV, or None."""
    root, ext = os.path.splitext(csv_path)
    path = (root if ext.lower() == ".csv" else csv_path) + ".resolved.json"
    try:
        with open(path) as f:
            r = json.load(f)
        return r if isinstance(r, dict) else None
    except (OSError, ValueError):
        return None


def title_of(csv_path, resolved):
    """The effective scenario: its name with the --set overrides on top of it,
    and what ran: the method and mode, or the commissioning (which measures
    the motor under no method). Lines of at most TITLE_WIDTH characters,
    what ran on a line of its own when the whole does not fit one."""
    name = os.path.splitext(os.path.basename(csv_path))[0]
    if resolved is None:
        return name
    scenario = resolved.get("scenario")
    if isinstance(scenario, str) and scenario:
        name = os.path.splitext(os.path.basename(scenario))[0]
    overrides = resolved.get("overrides")
    if isinstance(overrides, list) and overrides:
        name += " + " + ", ".join(str(o) for o in overrides)
    if resolved.get("commission") is True:
        what = "commissioning (measuring the motor)"
    else:
        ctrl = resolved.get("controller") if isinstance(resolved.get("controller"), dict) else {}
        what = ", ".join(str(ctrl[k]) + suffix for k, suffix in (("method", " DB-DTC"), ("mode", " mode"))
                         if k in ctrl)
    title = f"{name}: {what}" if what else name
    if len(title) <= TITLE_WIDTH or not what:
        return "\n".join(textwrap.wrap(title, TITLE_WIDTH))
    return "\n".join(textwrap.wrap(name, TITLE_WIDTH) + [what])


def span_floor(ax, values, min_span):
    """Widens ax's y-range to max(SPAN_REL x the largest |value|, min_span)
    about its middle, where the data alone would zoom below that."""
    finite = [v for v in values if math.isfinite(v)]
    if not finite:
        return
    need = max(SPAN_REL * max(abs(v) for v in finite), min_span)
    lo, hi = ax.get_ylim()
    if hi - lo < need:
        mid = 0.5 * (lo + hi)
        ax.set_ylim(mid - 0.5 * need, mid + 0.5 * need)


def read_columns(path):
    """The CSV's columns (metrics.load_csv), a drive_sil CSV's: PlotError naming the problem."""
    try:
        cols = metrics.load_csv(path)
    except OSError as e:
        raise PlotError(f"{path}: {e.strerror}") from None
    except ValueError as e:
        raise PlotError(str(e)) from None
    if "t_s" not in cols:
        raise PlotError(f"{path}: no t_s column (not a drive_sil CSV)")
    return cols


def has_values(values):
    return any(not math.isnan(v) for v in values)


def plant_series(name, cols, plant, n):
    """The plant's value over the run: its CSV column (R_ohm of a warming
    winding) or the constant of the resolved values (L_H, psif_Wb)."""
    if name in cols and has_values(cols[name]):
        return cols[name]
    v = plant.get(name)
    return [float(v)] * n if isinstance(v, (int, float)) else None


def draw_panel(ax, panel, cols, plant, t):
    """One panel: its series, the plant's value dashed beside the estimates,
    its unit, a span no narrower than its resolution, its legend."""
    ylabel, series, truth, k, min_span = panel
    for name, label, style in series:
        values = cols.get(name)
        if values is not None and has_values(values):
            ax.plot(t, [v * k for v in values], style, label=label, linewidth=1)
    if ax.lines:
        for name, label in truth:
            values = plant_series(name, cols, plant, len(t))
            if values is not None:
                ax.plot(t, [v * k for v in values], "k--", label=label, linewidth=0.8)
    ax.set_ylabel(ylabel)
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.grid(True, alpha=0.3)
    if ax.lines:
        span_floor(ax, [y for line in ax.lines for y in line.get_ydata()], min_span)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small")


def draw(plt, csv_path, out_path):
    cols = read_columns(csv_path)
    resolved = resolved_of(csv_path)
    plant = resolved.get("plant", {}) if resolved and isinstance(resolved.get("plant"), dict) else {}
    t = cols["t_s"]
    fig, axes = plt.subplots(len(PANELS), 1, sharex=True, figsize=FIG_SIZE_IN)
    try:
        for ax, panel in zip(axes, PANELS):
            draw_panel(ax, panel, cols, plant, t)
        axes[-1].set_xlabel("t [s]")
        axes[-1].ticklabel_format(axis="x", useOffset=False)
        title = title_of(csv_path, resolved)
        fig.suptitle(title)
        fig.subplots_adjust(**dict(LAYOUT, top=LAYOUT["top"] - TITLE_LINE * title.count("\n")))
        try:
            fig.savefig(out_path, dpi=DPI)
        except (OSError, ValueError) as e:
            raise PlotError(f"{out_path}: {e}") from None
    finally:
        plt.close(fig)


_plt = None


def load_matplotlib():
    """pyplot on the Agg backend (files only), or exit naming the venv."""
    global _plt
    if _plt is None:
        try:
            import matplotlib
            matplotlib.use("Agg")
            matplotlib.rcParams["axes.formatter.useoffset"] = False
            import matplotlib.pyplot as plt
        except ImportError:
            raise SystemExit("sil_plot.py: matplotlib is not installed for " + sys.executable + ";\n"
                             "  use `make plot CSV=RUN.csv` or build/venv/bin/sil-plot RUN.csv "
                             "(`make venv` builds build/venv)")
        _plt = plt
    return _plt


def plot_one(job):
    """(csv, out) -> None, or the error's message (in a worker process too)."""
    csv_path, out_path = job
    try:
        draw(load_matplotlib(), csv_path, out_path)
        return None
    except PlotError as e:
        return str(e)


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="sil_plot.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", metavar="RUN.csv", help="drive_sil CSV trace(s)")
    ap.add_argument("-o", "--out", metavar="OUT.png", help="the output file (one CSV only); default RUN.png")
    ap.add_argument("-j", "--jobs", type=int, default=1, metavar="N", help="processes drawing at once (default 1)")
    ap.add_argument("-q", "--quiet", action="store_true", help="no line per file written")
    a = ap.parse_args(argv)
    # Old form `sil_plot.py TRACE.csv OUT.png`: a second name with an image suffix is the output.
    if a.out is None and len(a.csv) == 2 and os.path.splitext(a.csv[1])[1].lower() in (".png", ".svg", ".pdf"):
        a.out = a.csv.pop()
    if a.out is not None and len(a.csv) != 1:
        ap.error("--out takes one CSV; with several, each RUN.csv gives RUN.png")
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    return a


def main(argv=None):
    a = parse_args(sys.argv[1:] if argv is None else argv)
    jobs = [(c, a.out or default_out(c)) for c in a.csv]
    for c, out in jobs:
        if os.path.abspath(c) == os.path.abspath(out):
            raise SystemExit(f"sil_plot.py: {c}: the output would overwrite the CSV")
    load_matplotlib()               # before forking: the workers inherit it, and a missing one is named once
    n = min(a.jobs, len(jobs))
    if n > 1:
        import multiprocessing
        with multiprocessing.get_context("fork").Pool(n) as pool:
            errors = pool.map(plot_one, jobs, chunksize=1)
    else:
        errors = [plot_one(j) for j in jobs]
    failed = 0
    for (c, out), err in zip(jobs, errors):
        if err is None:
            if not a.quiet:
                print(f"sil_plot: {out}")
        else:
            print(f"sil_plot.py: error: {err}", file=sys.stderr)
            failed += 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""sweep_maps.py - maps and report of the sweeps under a directory
(`make sweep`: build/sweep/<name>/results.csv from drivekit.sweep).

For each sweep with two grid columns, per figure (mean |Te - Te*| and mean
|psi_s - psi_s*|): the conventional and the proposed method side by side
on one shared logarithmic colour scale (green small, red large), cells
where the run ended faulted hatched and labelled with the fault's name,
the paper's six mismatch cases marked where they lie in the plane, and a
third panel with the ratio proposed / conventional (green: the proposed
method is better). A sweep with one grid column gets curves. Written as
DIR/<name>_<figure>.png; DIR/report.md links them, counts faults and
wins per sweep, and lists the worst points.

Usage: sweep_maps.py [--dir build/sweep] [--worst 5]
"""
import argparse
import collections
import csv
import json
import math
import os
import sys

from . import sweep, sweep_check
from .sweep_check import faulted

FIGURES = (("te_err_Nm", "mean |Te - Te*| [N m]"), ("psi_err_Wb", "mean |psi_s - psi_s*| [Wb]"))
METHODS = ("conventional", "proposed")
# The paper's mismatch cases (tools/scenarios/prop_*.ini): factor keys not named are 1.
PAPER_CASES = (("paper", {}), ("L066", {"controller.L_factor": 0.66}), ("L150", {"controller.L_factor": 1.5}),
               ("R430", {"controller.R_factor": 4.3}), ("psif050", {"controller.psif_factor": 0.5}),
               ("psif200", {"controller.psif_factor": 2.0}),
               ("L066_psif150", {"controller.L_factor": 0.66, "controller.psif_factor": 1.5}))
FACTOR_KEYS = ("controller.R_factor", "controller.L_factor", "controller.psif_factor")
PAPER_OP = {"speed_rpm": 500.0}     # the paper's operating point, at its 4 and 6 N m loads
PAPER_LOADS_NM = (4.0, 6.0)
RATIO_SPAN = 100.0                  # ratio colour scale 1/RATIO_SPAN .. RATIO_SPAN
LOG_SPACING_TOL = 1e-6
FIG_DPI = 110
SHORT_FAULT = 16                    # characters of a fault name written in a cell


def warned(r):
    """The run ended with a warning (e.g. step 1 refused, the drive fell back to conventional)."""
    return r.get("warning", "-") not in ("-", "")


def load(d):
    with open(os.path.join(d, sweep.RESULTS), newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == sweep.STATUS_OK]
    try:
        with open(os.path.join(d, sweep.DEFINITION)) as f:
            definition = json.load(f)
    except (OSError, ValueError):
        definition = {}
    grid_cols = sweep_check.grid_points(rows, sweep.RESULT_COLS)[0] if rows else []
    return rows, grid_cols, definition


def is_log(values):
    v = sorted(values)
    if len(v) < 3 or v[0] <= 0:
        return False
    r = [b / a for a, b in zip(v, v[1:])]
    return max(r) - min(r) < LOG_SPACING_TOL * max(r)


def edges(values, log):
    """Cell edges around sorted grid values (geometric midpoints on a log axis)."""
    v = sorted(values)
    if len(v) == 1:
        return [v[0] * 0.9, v[0] * 1.1] if log else [v[0] - 0.5, v[0] + 0.5]
    f = (lambda a, b: math.sqrt(a * b)) if log else (lambda a, b: 0.5 * (a + b))
    mid = [f(a, b) for a, b in zip(v, v[1:])]
    first = v[0] * v[0] / mid[0] if log else 2 * v[0] - mid[0]
    last = v[-1] * v[-1] / mid[-1] if log else 2 * v[-1] - mid[-1]
    return [first] + mid + [last]


def paper_marks(grid_cols, definition):
    """(label, x, y) of the paper's cases in this plane: every factor not on an axis must be 1."""
    sets = " ".join(definition.get("set", []))
    marks = []
    if set(grid_cols) <= set(FACTOR_KEYS):
        for label, case in PAPER_CASES:
            off_axis = [k for k in case if k not in grid_cols]
            if off_axis or any(k in sets for k in FACTOR_KEYS if k not in grid_cols):
                continue
            marks.append((label, case.get(grid_cols[0], 1.0), case.get(grid_cols[1], 1.0)))
    elif grid_cols == ["speed_rpm", "load_Nm"]:
        marks = [(f"paper {t:g} N m", PAPER_OP["speed_rpm"], t) for t in PAPER_LOADS_NM]
    return marks


# The grid of a 2-D sweep: its keys, values and cell edges on each axis.
Plane = collections.namedtuple("Plane", "xk yk xs ys xe ye xlog ylog")


def plane_of(rows, grid_cols):
    xk, yk = grid_cols
    xs = sorted({float(r[xk]) for r in rows})
    ys = sorted({float(r[yk]) for r in rows})
    xlog, ylog = is_log(xs), is_log(ys)
    return Plane(xk, yk, xs, ys, edges(xs, xlog), edges(ys, ylog), xlog, ylog)


def method_grids(cell, pl, fig_key):
    """{method: rows of fig_key over the plane}, NaN where the run faulted or gave no positive value."""
    grids = {}
    for m in METHODS:
        grids[m] = [[math.nan] * len(pl.xs) for _ in pl.ys]
        for i, y in enumerate(pl.ys):
            for j, x in enumerate(pl.xs):
                r = cell.get((m, x, y))
                if r is not None and not faulted(r):
                    v = float(r[fig_key])
                    grids[m][i][j] = v if v > 0 else math.nan
    return grids


def hatch_cells(ax, cell, m, pl):
    """Method m's cells with a warning dotted, the faulted ones crossed and labelled with the fault."""
    xe, ye = pl.xe, pl.ye
    for i, y in enumerate(pl.ys):
        for j, x in enumerate(pl.xs):
            r = cell.get((m, x, y))
            if r is not None and warned(r) and not faulted(r):
                ax.fill_between([xe[j], xe[j + 1]], ye[i], ye[i + 1], facecolor="none",
                                edgecolor="k", hatch="..", linewidth=0)
            if r is not None and faulted(r):
                ax.fill_between([xe[j], xe[j + 1]], ye[i], ye[i + 1], facecolor="none",
                                edgecolor="k", hatch="xx", linewidth=0)
                ax.text(math.sqrt(xe[j] * xe[j + 1]) if pl.xlog else 0.5 * (xe[j] + xe[j + 1]),
                        math.sqrt(ye[i] * ye[i + 1]) if pl.ylog else 0.5 * (ye[i] + ye[i + 1]),
                        r["fault_name"][:SHORT_FAULT], ha="center", va="center", fontsize=6,
                        rotation=30, bbox=dict(facecolor="white", alpha=0.7, linewidth=0, pad=0.5))


def plane_axes(ax, pl, marks):
    """The plane's scales, limits and ticks on ax, and the paper's cases marked."""
    ax.set_xscale("log" if pl.xlog else "linear")
    ax.set_yscale("log" if pl.ylog else "linear")
    ax.set_xlim(pl.xe[0], pl.xe[-1])
    ax.set_ylim(pl.ye[0], pl.ye[-1])
    ax.set_xlabel(pl.xk)
    ax.set_ylabel(pl.yk)
    ax.set_xticks(pl.xs)
    ax.set_yticks(pl.ys)
    ax.set_xticklabels([f"{x:.4g}" for x in pl.xs], fontsize=7, rotation=45)
    ax.set_yticklabels([f"{y:.4g}" for y in pl.ys], fontsize=7)
    ax.minorticks_off()
    for label, x, y in marks:
        ax.plot([x], [y], marker="o", markersize=7, markerfacecolor="none", markeredgecolor="blue")
        ax.annotate(label, (x, y), textcoords="offset points", xytext=(5, 5), fontsize=7, color="blue")


def plot_2d(plt, colors, rows, grid_cols, definition, name, out_dir):
    pl = plane_of(rows, grid_cols)
    cell = {(r["method"], float(r[pl.xk]), float(r[pl.yk])): r for r in rows}
    marks = paper_marks(grid_cols, definition)
    written = []
    for fig_key, fig_label in FIGURES:
        grids = method_grids(cell, pl, fig_key)
        finite = [v for m in METHODS for row in grids[m] for v in row if math.isfinite(v)]
        if not finite:
            continue
        norm = colors.LogNorm(vmin=min(finite), vmax=max(max(finite), min(finite) * 1.0001))
        fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), constrained_layout=True)
        cmap = plt.get_cmap("RdYlGn_r").copy()
        cmap.set_bad("0.85")
        for ax, m in zip(axes, METHODS):
            pc = ax.pcolormesh(pl.xe, pl.ye, grids[m], norm=norm, cmap=cmap, shading="flat")
            hatch_cells(ax, cell, m, pl)
            ax.set_title(f"{m}: {fig_label}")
        fig.colorbar(pc, ax=list(axes[:2]), label=fig_label)
        ratio = [[grids["proposed"][i][j] / grids["conventional"][i][j]
                  if math.isfinite(grids["proposed"][i][j]) and math.isfinite(grids["conventional"][i][j])
                  else math.nan for j in range(len(pl.xs))] for i in range(len(pl.ys))]
        rc = axes[2].pcolormesh(pl.xe, pl.ye, ratio, cmap=cmap, shading="flat",
                                norm=colors.LogNorm(vmin=1.0 / RATIO_SPAN, vmax=RATIO_SPAN))
        axes[2].set_title("ratio proposed / conventional (< 1: proposed better)")
        fig.colorbar(rc, ax=axes[2], label="proposed / conventional")
        for ax in axes:
            plane_axes(ax, pl, marks)
        fig.suptitle(f"{name}: {fig_label}; hatched: run ended faulted (fault named); dotted: a warning; "
                     f"blue: the paper's cases")
        png = f"{name}_{fig_key}.png"
        fig.savefig(os.path.join(out_dir, png), dpi=FIG_DPI)
        plt.close(fig)
        written.append(png)
    return written


def plot_1d(plt, rows, grid_cols, name, out_dir):
    (xk,) = grid_cols
    xs = sorted({float(r[xk]) for r in rows})
    fig, axes = plt.subplots(1, len(FIGURES), figsize=(12, 4.2), constrained_layout=True)
    for ax, (fig_key, fig_label) in zip(axes, FIGURES):
        for m in METHODS:
            pts = sorted((float(r[xk]), r) for r in rows if r["method"] == m)
            ok = [(x, float(r[fig_key])) for x, r in pts if not faulted(r)]
            line, = ax.plot([p[0] for p in ok], [p[1] for p in ok], marker=".", label=m)
            for x, r in pts:
                if faulted(r):
                    ax.axvline(x, color=line.get_color(), linestyle=":", linewidth=1)
                    ax.annotate(r["fault_name"], (x, 1), xycoords=("data", "axes fraction"), rotation=90,
                                va="top", fontsize=7, color=line.get_color())
        ax.set_yscale("log")
        ax.set_xscale("log" if is_log(xs) else "linear")
        ax.set_xlabel(xk)
        ax.set_ylabel(fig_label)
        ax.legend()
    fig.suptitle(f"{name}; dotted: run ended faulted")
    png = f"{name}_curves.png"
    fig.savefig(os.path.join(out_dir, png), dpi=FIG_DPI)
    plt.close(fig)
    return [png]


def fmt(v, spec=".4g"):
    try:
        x = float(v)
    except (TypeError, ValueError):
        return str(v)
    return format(x, spec) if math.isfinite(x) else "-"


def summary_lines(name, rows, grid_cols, definition, pngs, worst_n):
    out = [f"## {name}", ""]
    if definition:
        out.append("Grid: " + ", ".join(f"`{g}`" for g in definition.get("grid_names", grid_cols)) +
                   ("; overrides: " + ", ".join(f"`{s}`" for s in definition.get("set", []))
                    if definition.get("set") else "") + ".")
        out.append("")
    by_point = sweep_check.grid_points(rows, sweep.RESULT_COLS)[1]
    n = len(by_point)
    fault = {m: sum(1 for p in by_point.values() if m in p and faulted(p[m])) for m in METHODS}
    only_prop = sum(1 for p in by_point.values() if len(p) == 2 and faulted(p["proposed"]) and not faulted(p["conventional"]))
    pairs = [(float(p["conventional"]["te_err_Nm"]), float(p["proposed"]["te_err_Nm"]))
             for p in by_point.values() if len(p) == 2 and not faulted(p["conventional"]) and not faulted(p["proposed"])]
    wins = sum(1 for c, p in pairs if p <= c)
    ratios = sorted(p / c for c, p in pairs if c > 0)
    bad, _ = sweep_check.violations(by_point, sweep_check.TOL_NM)
    out.append(f"**The rule** (proposed never faulted where the conventional method is not, never worse "
               f"than it + {sweep_check.TOL_NM:g} N m; `sweep-check`) **"
               f"{'holds' if not bad else 'broken'}** here" +
               (": " + "; ".join(f"{sweep_check.at_text(grid_cols, k)}: {why}" for k, why in bad) if bad else "") +
               ".")
    out.append("")
    out.append(f"{n} points. Faulted: conventional {fault['conventional']}, proposed {fault['proposed']} "
               f"(proposed only: {only_prop}). Where both ran, the proposed method's mean |Te - Te*| is "
               f"lower or equal at {wins} of {len(pairs)} points" +
               (f"; median ratio proposed / conventional {ratios[len(ratios) // 2]:.3g}, "
                f"worst {ratios[-1]:.3g}." if ratios else "."))
    out.append("")
    for png in pngs:
        out.append(f"![{png}]({png})")
        out.append("")
    warn = {m: sum(1 for p in by_point.values() if m in p and warned(p[m])) for m in METHODS}
    if any(warn.values()):
        out.append(f"Runs ending with a warning (drive_sil's `warning`, e.g. step 1 refused and the drive "
                   f"fell back to the conventional method): conventional {warn['conventional']}, "
                   f"proposed {warn['proposed']}; their cells are dotted.")
        out.append("")
    head = ["method"] + grid_cols + ["te_err_Nm", "psi_err_Wb", "te_ripple_Nm", "max_abs_i_A", "fault_name"]
    out.append(f"Worst {worst_n} points per method (faulted first, then by mean |Te - Te*|):")
    out.append("")
    out.append("| " + " | ".join(head) + " |")
    out.append("|" + " --- |" * len(head))
    for m in METHODS:
        mine = [r for r in rows if r["method"] == m]
        mine.sort(key=lambda r: (not faulted(r), -(float(r["te_err_Nm"]) if math.isfinite(float(r["te_err_Nm"]))
                                                    else math.inf)))
        for r in mine[:worst_n]:
            out.append("| " + " | ".join([m] + [fmt(r[c]) for c in head[1:-1]] + [r["fault_name"]]) + " |")
    out.append("")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", default=os.path.join("build", "sweep"))
    ap.add_argument("--worst", type=int, default=5)
    a = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.colors as colors
    import matplotlib.pyplot as plt
    names = sorted(n for n in os.listdir(a.dir) if os.path.isfile(os.path.join(a.dir, n, sweep.RESULTS)))
    if not names:
        print(f"sweep_maps.py: {a.dir}: no */{sweep.RESULTS}", file=sys.stderr)
        return 1
    lines = ["# Sensitivity maps", "",
             "Each sweep runs the scenario `tools/scenarios/prop_paper.ini` (500 r/min, the paper's "
             "timeline and its steady window 0.8-0.95 s) over a grid, both methods at every point "
             "(`make sweep`, `sil-sweep`). Colours: mean over the window, one logarithmic scale per "
             "figure shared by both methods (green small, red large); grey hatched cells ended faulted "
             "(the fault is named); blue circles are the paper's cases. `*_real` sweeps add a realistic "
             "board: ADC noise 0.02 A, 1 us dead time compensated as 0.9 us, 1000-line encoder.", ""]
    for name in names:
        d = os.path.join(a.dir, name)
        rows, grid_cols, definition = load(d)
        if not rows:
            continue
        if len(grid_cols) == 2:
            pngs = plot_2d(plt, colors, rows, grid_cols, definition, name, a.dir)
        elif len(grid_cols) == 1:
            pngs = plot_1d(plt, rows, grid_cols, name, a.dir)
        else:
            pngs = []
        lines += summary_lines(name, rows, grid_cols, definition, pngs, a.worst)
    path = os.path.join(a.dir, "report.md")
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        f.write("\n".join(lines))
    os.replace(tmp, path)
    print(f"sweep_maps.py: {len(names)} sweeps -> {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

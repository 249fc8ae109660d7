#!/usr/bin/env python3
"""sil_plot.py CSV PNG - plot one drive_sil trace with the paper's panels:
speed, torque (ref/true/est), stator flux (ref/true/est), id/iq, ud/uq,
and the controller's parameter estimates. NaN columns (no value in the
run's mode) simply draw nothing."""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

FIG_SIZE_IN = (10, 14)
DPI = 110


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise SystemExit(f"sil_plot: {path}: empty file")
    header, data = rows[0], rows[1:]
    cols = {name: [] for name in header}
    for line_no, row in enumerate(data, start=2):
        if len(row) != len(header):
            raise SystemExit(f"sil_plot: {path}:{line_no}: {len(row)} fields, header has {len(header)}")
        for name, text in zip(header, row):
            cols[name].append(float(text))
    return cols


def has_values(values):
    return any(not math.isnan(v) for v in values)


PANELS = [
    ("speed [r/min]", [("speed_ref_rpm", "ref", "--"), ("speed_rpm", "true", "-"), ("speed_est_rpm", "est", ":")]),
    ("torque [N m]", [("te_ref_Nm", "ref", "--"), ("te_Nm", "true", "-"), ("te_est_Nm", "est", ":"),
                      ("load_Nm", "load", "-.")]),
    ("stator flux [Wb]", [("psi_ref_Wb", "ref", "--"), ("psi_Wb", "true", "-"), ("psi_est_Wb", "est", ":")]),
    ("current [A]", [("id_A", "id", "-"), ("iq_A", "iq", "-")]),
    ("voltage [V]", [("ud_V", "ud applied", "-"), ("uq_V", "uq applied", "-"),
                     ("ud_cmd_V", "ud cmd", ":"), ("uq_cmd_V", "uq cmd", ":")]),
    ("estimates", [("R_est_ohm", "R [ohm]", "-"), ("L_est_H", "L [mH]", "-"),
                   ("psif_est_Wb", "psi_f [0.1 Wb]", "-"), ("fd_est", "fd", ":"), ("fq_est", "fq", ":")]),
]
# Scales that put the estimates on one axis: L in mH, psi_f in tenths of Wb.
SCALE = {"L_est_H": 1000.0, "psif_est_Wb": 10.0}


def main(argv):
    if len(argv) != 3:
        raise SystemExit("usage: sil_plot.py TRACE.csv OUT.png")
    cols = read_columns(argv[1])
    t = cols["t_s"]
    fig, axes = plt.subplots(len(PANELS), 1, sharex=True, figsize=FIG_SIZE_IN)
    for ax, (ylabel, series) in zip(axes, PANELS):
        for name, label, style in series:
            values = cols.get(name)
            if values is not None and has_values(values):
                k = SCALE.get(name, 1.0)
                ax.plot(t, [v * k for v in values], style, label=label, linewidth=1)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if ax.lines:
            ax.legend(loc="best", fontsize="small")
    axes[-1].set_xlabel("t [s]")
    fig.suptitle(argv[1])
    fig.tight_layout()
    fig.savefig(argv[2], dpi=DPI)
    print(f"sil_plot: {argv[2]}")


if __name__ == "__main__":
    main(sys.argv)

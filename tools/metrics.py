#!/usr/bin/env python3
"""metrics.py - figures of one SIL run from its CSV (hal/sim/sil.h columns).
Standard library only, so it runs wherever python3 does.

True plant values (te_Nm, psi_Wb, speed_rpm) are compared with the
controller's references (te_ref_Nm, psi_ref_Wb, speed_ref_rpm):

  steady window (--window A:B, seconds):
    te_err_Nm       mean |Te - Te*|
    te_ripple_Nm    RMS of Te - Te* (the torque ripple around the reference)
    psi_err_Wb      mean |psi_s - psi_s*|, psi_err_pct the same relative to psi_s*
    speed_err_rpm   mean of speed - speed*, speed_err_max_rpm max |.|
    id_A, iq_A      means of the true currents
  torque step (the largest jump of Te* in the run, the last of equal ones, torque mode):
    step_periods_95 periods from the row that first carries the new Te*
                    (the ISR that took the command) to Te within 95 % of the step
    step_overshoot_pct  max overshoot after it, in % of the step
    step_settle_periods periods until Te stays within 2 % of the step
  load step (--load-window A:B, speed mode):
    recovery_ms     time from A until the speed stays within 1 r/min
    speed_dip_rpm   largest speed - speed* below zero in A..B, as a positive number
  estimates (--truth R:L:psif, the plant's values; columns R_est_ohm,
  L_est_H, psif_est_Wb, est):
    R_err_pct, L_err_pct, psif_err_pct  mean of (x^ - x)/x over the steady window
    t2_L_ms, t2_psif_ms  time from step 2's start (first row with est = 2)
                    until the estimate stays within 2 % up to the window's end
                    (None: no step 2, or never)

Usage: metrics.py RUN.csv [--window 0.8:0.95] [--load-window 0.95:1.05]
                  [--truth 3:0.011:0.24] [--Ts 1e-4] [--json]
"""
import argparse
import csv
import json
import math
import sys

SPEED_BAND_RPM = 1.0      # recovery band after a load step
STEP_REACH = 0.95         # fraction of the torque step counted as reached
SETTLE_BAND = 0.02        # settling band, fraction of the torque step
STEP_MIN_NM = 1e-3        # a Te* jump smaller than this is no step
MAX_STEPS = 4             # more jumps than this: Te* is not a step profile
EST_BAND = 0.02           # convergence band of the estimates, fraction of the true value
EST_STEP2 = 2             # ctrl_est_t CTRL_EST_STEP2 in the est column
EST_COLS = (("R", "R_est_ohm"), ("L", "L_est_H"), ("psif", "psif_est_Wb"))


def load_csv(path):
    """Columns of the CSV as lists of floats, by header name ("nan" allowed)."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r]
    if len(rows) < 2:
        raise ValueError(f"{path}: no data rows")
    head = rows[0]
    cols = {name: [] for name in head}
    for r in rows[1:]:
        for name, x in zip(head, r):
            cols[name].append(float(x))
    return cols


def parse_window(text):
    a, b = text.split(":")
    return float(a), float(b)


def _mean(xs):
    xs = [x for x in xs if math.isfinite(x)]
    return sum(xs) / len(xs) if xs else math.nan


def _max(xs):
    xs = [x for x in xs if math.isfinite(x)]
    return max(xs) if xs else math.nan


def steady(col, t0, t1):
    idx = [i for i, t in enumerate(col["t_s"]) if t0 <= t < t1]
    if not idx:
        raise ValueError(f"window {t0}:{t1} s holds no rows")
    g = lambda name: [col[name][i] for i in idx]
    e_te = [a - b for a, b in zip(g("te_Nm"), g("te_ref_Nm"))]
    e_psi = [a - b for a, b in zip(g("psi_Wb"), g("psi_ref_Wb"))]
    e_w = [a - b for a, b in zip(g("speed_rpm"), g("speed_ref_rpm"))]
    return {
        "te_err_Nm": _mean([abs(e) for e in e_te]),
        "te_ripple_Nm": math.sqrt(_mean([e * e for e in e_te])),
        "psi_err_Wb": _mean([abs(e) for e in e_psi]),
        "psi_err_pct": 100.0 * _mean([abs(e) / r for e, r in zip(e_psi, g("psi_ref_Wb"))]),
        "speed_err_rpm": _mean(e_w),
        "speed_err_max_rpm": _max([abs(e) for e in e_w]),
        "id_A": _mean(g("id_A")),
        "iq_A": _mean(g("iq_A")),
    }


def torque_step(col, Ts):
    """Response to the largest jump of Te* (None when Te* is no step profile)."""
    ref = [r if math.isfinite(r) else 0.0 for r in col["te_ref_Nm"]]
    te = col["te_Nm"]
    t = col["t_s"]
    if len(ref) < 3:
        return None
    d = [abs(b - a) for a, b in zip(ref, ref[1:])]
    if sum(1 for x in d if x >= STEP_MIN_NM) > MAX_STEPS:
        return None                     # a moving reference (speed mode)
    # first row with the new reference; of equal jumps the last (a step after a set-up sequence)
    j = max(range(len(d)), key=lambda i: (d[i], i)) + 1
    if d[j - 1] < STEP_MIN_NM:
        return None
    te0, te1 = ref[j - 1], ref[j]
    step = te1 - te0
    frac = [(x - te0) / step for x in te[j:]]
    periods = lambda i: int(round((t[j + i] - t[j]) / Ts))
    reached = next((i for i, f in enumerate(frac) if f >= STEP_REACH), None)
    out = {"step_from_Nm": te0, "step_to_Nm": te1, "step_t_s": t[j]}
    out["step_periods_95"] = periods(reached) if reached is not None else None
    out["step_overshoot_pct"] = 100.0 * max(0.0, _max(frac) - 1.0)
    outside = [i for i, f in enumerate(frac) if abs(f - 1.0) > SETTLE_BAND]
    if not outside:
        out["step_settle_periods"] = 0
    elif outside[-1] + 1 < len(frac):
        out["step_settle_periods"] = periods(outside[-1] + 1)
    else:
        out["step_settle_periods"] = None   # never settled
    return out


def load_recovery(col, t0, t1):
    """ms from t0 until |speed error| stays within the band up to t1 (None: never)."""
    idx = [i for i, t in enumerate(col["t_s"]) if t0 <= t < t1]
    if not idx:
        return None
    e = [abs(col["speed_rpm"][i] - col["speed_ref_rpm"][i]) for i in idx]
    out = [k for k, x in enumerate(e) if x > SPEED_BAND_RPM]
    if not out:
        return 0.0
    if out[-1] + 1 >= len(e):
        return None
    return 1e3 * (col["t_s"][idx[out[-1] + 1]] - t0)


def speed_dip(col, t0, t1):
    """Largest speed shortfall [r/min] below the reference in t0..t1 (0 if none)."""
    idx = [i for i, t in enumerate(col["t_s"]) if t0 <= t < t1]
    if not idx:
        return None
    return max(0.0, _max([col["speed_ref_rpm"][i] - col["speed_rpm"][i] for i in idx]))


def step2_start(col):
    """t of the first row with est = step 2 (None without one)."""
    est = col.get("est")
    if est is None:
        return None
    return next((t for t, e in zip(col["t_s"], est) if e == EST_STEP2), None)


def estimates(col, truth, t0, t1):
    """Relative errors of R^, L^, psi_f^ against truth = (R, L, psif), and
    the time from step 2's start until L^ and psi_f^ stay within the band."""
    out = {}
    idx = [i for i, t in enumerate(col["t_s"]) if t0 <= t < t1]
    ts2 = step2_start(col)
    out["t_step2_s"] = ts2
    for (name, c), x0 in zip(EST_COLS, truth):
        if c not in col or not idx:
            continue
        out[f"{name}_err_pct"] = 100.0 * _mean([(col[c][i] - x0) / x0 for i in idx])
        if name == "R":
            continue
        key = f"t2_{name}_ms"
        out[key] = None
        if ts2 is None:
            continue
        rows = [i for i, t in enumerate(col["t_s"]) if ts2 <= t < t1]
        bad = [i for i in rows if not abs(col[c][i] - x0) <= EST_BAND * x0]
        if not bad:
            out[key] = 0.0
        elif bad[-1] != rows[-1]:
            out[key] = 1e3 * (col["t_s"][bad[-1] + 1] - ts2)
    return out


def compute(path, window=(0.8, 0.95), load_window=None, Ts=1e-4, truth=None):
    col = load_csv(path)
    for need in ("t_s", "te_Nm", "te_ref_Nm", "psi_Wb", "psi_ref_Wb", "speed_rpm", "speed_ref_rpm"):
        if need not in col:
            raise ValueError(f"{path}: column {need} missing")
    res = {"csv": path}
    res.update(steady(col, *window))
    ts = torque_step(col, Ts)
    if ts is not None:
        res.update(ts)
    if load_window is not None:
        res["recovery_ms"] = load_recovery(col, *load_window)
        res["speed_dip_rpm"] = speed_dip(col, *load_window)
    if truth is not None:
        res.update(estimates(col, truth, *window))
    st = col.get("state")
    res["final_state"] = int(st[-1]) if st else None
    return res


def fmt(v, spec):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, spec)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--window", default="0.8:0.95", help="steady window t0:t1 [s]")
    ap.add_argument("--load-window", default=None, help="load step t0:t1 [s] for the speed recovery")
    ap.add_argument("--Ts", type=float, default=1e-4, help="control period [s]")
    ap.add_argument("--truth", default=None, help="plant R:L:psif for the estimates' errors")
    ap.add_argument("--json", action="store_true", help="print JSON instead of text")
    a = ap.parse_args(argv)
    try:
        truth = tuple(float(x) for x in a.truth.split(":")) if a.truth else None
        res = compute(a.csv, parse_window(a.window),
                      parse_window(a.load_window) if a.load_window else None, a.Ts, truth)
    except (OSError, ValueError) as e:
        print(f"metrics.py: {e}", file=sys.stderr)
        return 1
    if a.json:
        print(json.dumps(res, indent=1))
        return 0
    print(f"{a.csv}  window {a.window} s")
    print(f"  mean |Te - Te*|      {fmt(res['te_err_Nm'], '.4f')} N m   (ripple, RMS {fmt(res['te_ripple_Nm'], '.4f')} N m)")
    print(f"  mean |psi - psi*|    {fmt(res['psi_err_Wb'], '.5f')} Wb  ({fmt(res['psi_err_pct'], '.3f')} %)")
    print(f"  speed error          {fmt(res['speed_err_rpm'], '+.3f')} r/min mean, {fmt(res['speed_err_max_rpm'], '.3f')} max")
    print(f"  id, iq               {fmt(res['id_A'], '+.4f')} A, {fmt(res['iq_A'], '.4f')} A")
    if "step_periods_95" in res:
        print(f"  torque step {res['step_from_Nm']:.2f} -> {res['step_to_Nm']:.2f} N m at {res['step_t_s']:.4f} s: "
              f"95 % in {fmt(res['step_periods_95'], 'd')} periods, overshoot {res['step_overshoot_pct']:.2f} %, "
              f"settled (2 %) after {fmt(res['step_settle_periods'], 'd')} periods")
    if "recovery_ms" in res:
        print(f"  speed back within {SPEED_BAND_RPM:g} r/min after {fmt(res['recovery_ms'], '.1f')} ms, "
              f"dip {fmt(res['speed_dip_rpm'], '.2f')} r/min")
    if "R_err_pct" in res:
        print(f"  estimates: R {fmt(res['R_err_pct'], '+.3f')} %, L {fmt(res.get('L_err_pct'), '+.3f')} %, "
              f"psi_f {fmt(res.get('psif_err_pct'), '+.3f')} %; within 2 % after step 2 "
              f"(t = {fmt(res['t_step2_s'], '.3f')} s): L {fmt(res.get('t2_L_ms'), '.1f')} ms, "
              f"psi_f {fmt(res.get('t2_psif_ms'), '.1f')} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())

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
  torque step (the largest jump of Te* in the run, torque mode):
    step_periods_95 periods from the row that first carries the new Te*
                    (the ISR that took the command) to Te within 95 % of the step
    step_overshoot_pct  max overshoot after it, in % of the step
    step_settle_periods periods until Te stays within 2 % of the step
  load step (--load-window A:B, speed mode):
    recovery_ms     time from A until the speed stays within 1 r/min

Usage: metrics.py RUN.csv [--window 0.8:0.95] [--load-window 0.95:1.05]
                  [--Ts 1e-4] [--json]
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
    j = max(range(len(d)), key=lambda i: d[i]) + 1   # first row with the new reference
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


def compute(path, window=(0.8, 0.95), load_window=None, Ts=1e-4):
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
    ap.add_argument("--json", action="store_true", help="print JSON instead of text")
    a = ap.parse_args(argv)
    try:
        res = compute(a.csv, parse_window(a.window),
                      parse_window(a.load_window) if a.load_window else None, a.Ts)
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
        print(f"  speed back within {SPEED_BAND_RPM:g} r/min after {fmt(res['recovery_ms'], '.1f')} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())

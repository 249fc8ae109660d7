#!/usr/bin/env python3
"""metrics.py - figures of one SIL run from its CSV (tools/sil/sil.h columns).
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
                    (both None when speed* is nan there: no speed reference)
  estimates (--truth R:L:psif, the plant's values; columns R_est_ohm,
  L_est_H, psif_est_Wb, est):
    R_err_pct, L_err_pct, psif_err_pct  mean of (x^ - x)/x over the steady window
                    (R against the CSV's R_ohm column of each row when present)
    t2_L_ms, t2_psif_ms  time from step 2's start (first row with est = 2)
                    until the estimate stays within 2 % up to the window's end
                    (None: no step 2, or never)

Bad input (missing file or column, a row with the wrong number of fields,
a malformed number, a window holding no rows, a malformed --window or
--truth) prints "metrics.py: FILE...: problem" and exits 1. Figures that
have no value in the run's mode (a nan reference column) are None, "-" in
the text and null in the JSON.

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


REQUIRED_COLS = ("t_s", "te_Nm", "te_ref_Nm", "psi_Wb", "psi_ref_Wb", "speed_rpm", "speed_ref_rpm",
                 "id_A", "iq_A")


def load_csv(path):
    """Columns of the CSV as lists of floats, by header name ("nan" allowed).
    ValueError naming the file and line for a short/long row or a malformed number."""
    with open(path, newline="") as f:
        try:
            rows = [(n, r) for n, r in enumerate(csv.reader(f), start=1) if r]
        except (csv.Error, UnicodeDecodeError) as e:      # e.g. the PNG given for the CSV
            raise ValueError(f"{path}: not a CSV ({e})") from None
    if len(rows) < 2:
        raise ValueError(f"{path}: no data rows")
    head = rows[0][1]
    cols = {name: [] for name in head}
    for n, r in rows[1:]:
        if len(r) != len(head):
            raise ValueError(f"{path}:{n}: {len(r)} fields, the header has {len(head)}")
        for name, x in zip(head, r):
            try:
                cols[name].append(float(x))
            except ValueError:
                raise ValueError(f"{path}:{n}: column {name}: malformed number {x!r}") from None
    return cols


def parse_window(text):
    """'t0:t1' in seconds, t0 < t1."""
    try:
        a, b = (float(x) for x in text.split(":"))
    except ValueError:
        raise ValueError(f"window {text!r}: expected T0:T1 in seconds") from None
    if not a < b:
        raise ValueError(f"window {text!r}: T0 must be below T1")
    return a, b


def parse_truth(text):
    """'R:L:psif', three positive numbers."""
    try:
        vals = tuple(float(x) for x in text.split(":"))
    except ValueError:
        vals = ()
    if len(vals) != 3 or not all(math.isfinite(v) and v > 0 for v in vals):
        raise ValueError(f"truth {text!r}: expected R:L:psif, three positive numbers")
    return vals


def _mean(xs):
    xs = [x for x in xs if math.isfinite(x)]
    return sum(xs) / len(xs) if xs else math.nan


def _max(xs):
    xs = [x for x in xs if math.isfinite(x)]
    return max(xs) if xs else math.nan


def _rows(col, t0, t1, what):
    idx = [i for i, t in enumerate(col["t_s"]) if t0 <= t < t1]
    if not idx:
        raise ValueError(f"{what} {t0:g}:{t1:g} s holds no rows "
                         f"(the run has t = {col['t_s'][0]:g} .. {col['t_s'][-1]:g} s)")
    return idx


def steady(col, t0, t1):
    idx = _rows(col, t0, t1, "window")
    g = lambda name: [col[name][i] for i in idx]
    e_te = [a - b for a, b in zip(g("te_Nm"), g("te_ref_Nm"))]
    e_psi = [a - b for a, b in zip(g("psi_Wb"), g("psi_ref_Wb"))]
    e_w = [a - b for a, b in zip(g("speed_rpm"), g("speed_ref_rpm"))]
    return {
        "te_err_Nm": _mean([abs(e) for e in e_te]),
        "te_ripple_Nm": math.sqrt(_mean([e * e for e in e_te])),
        "psi_err_Wb": _mean([abs(e) for e in e_psi]),
        "psi_err_pct": 100.0 * _mean([abs(e) / r if r > 0 else math.nan
                                       for e, r in zip(e_psi, g("psi_ref_Wb"))]),
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
    """ms from t0 until |speed error| stays within the band up to t1 (None: never,
    or no speed reference in the window: speed_ref_rpm is nan outside speed mode)."""
    idx = _rows(col, t0, t1, "load window")
    e = [abs(col["speed_rpm"][i] - col["speed_ref_rpm"][i]) for i in idx]
    if not any(math.isfinite(x) for x in e):
        return None
    out = [k for k, x in enumerate(e) if not x <= SPEED_BAND_RPM]    # nan counts as outside
    if not out:
        return 0.0
    if out[-1] + 1 >= len(e):
        return None
    return 1e3 * (col["t_s"][idx[out[-1] + 1]] - t0)


def speed_dip(col, t0, t1):
    """Largest speed shortfall [r/min] below the reference in t0..t1 (0 if none;
    None without a speed reference in the window)."""
    idx = _rows(col, t0, t1, "load window")
    m = _max([col["speed_ref_rpm"][i] - col["speed_rpm"][i] for i in idx])
    return max(0.0, m) if math.isfinite(m) else None


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
        if name == "R" and "R_ohm" in col:
            # the plant's R of each row (a warming winding), when the CSV has it
            out[f"{name}_err_pct"] = 100.0 * _mean([(col[c][i] - col["R_ohm"][i]) / col["R_ohm"][i] for i in idx])
        else:
            out[f"{name}_err_pct"] = 100.0 * _mean([(col[c][i] - x0) / x0 for i in idx])
        if name == "R":
            continue
        key = f"t2_{name}_ms"
        out[key] = None
        if ts2 is None:
            continue
        rows = [i for i, t in enumerate(col["t_s"]) if ts2 <= t < t1]
        if not rows:
            continue                    # step 2 starts at or after the window's end
        bad = [i for i in rows if not abs(col[c][i] - x0) <= EST_BAND * x0]
        if not bad:
            out[key] = 0.0
        elif bad[-1] != rows[-1]:
            out[key] = 1e3 * (col["t_s"][bad[-1] + 1] - ts2)
    return out


def compute(path, window=(0.8, 0.95), load_window=None, Ts=1e-4, truth=None):
    """Every figure of one run. ValueError (message names the file) on bad input."""
    if not Ts > 0:
        raise ValueError(f"Ts {Ts!r}: must be positive")
    if truth is not None and (len(truth) != 3 or not all(math.isfinite(x) and x > 0 for x in truth)):
        raise ValueError(f"truth {truth!r}: expected (R, L, psif), three positive numbers")
    col = load_csv(path)
    missing = [need for need in REQUIRED_COLS if need not in col]
    if missing:
        raise ValueError(f"{path}: column{'s' if len(missing) > 1 else ''} {', '.join(missing)} missing")
    res = {"csv": path}
    try:
        res.update(steady(col, *window))
        ts = torque_step(col, Ts)
        if ts is not None:
            res.update(ts)
        if load_window is not None:
            res["recovery_ms"] = load_recovery(col, *load_window)
            res["speed_dip_rpm"] = speed_dip(col, *load_window)
        if truth is not None:
            res.update(estimates(col, truth, *window))
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    st = col.get("state")
    res["final_state"] = int(st[-1]) if st and math.isfinite(st[-1]) else None
    return res


def json_safe(res):
    """nan/inf as null: JSON has no NaN (json.dumps would write the invalid token NaN)."""
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in res.items()}


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
        truth = parse_truth(a.truth) if a.truth else None
        res = compute(a.csv, parse_window(a.window),
                      parse_window(a.load_window) if a.load_window else None, a.Ts, truth)
    except (OSError, ValueError) as e:
        print(f"metrics.py: {e}", file=sys.stderr)
        return 1
    if a.json:
        print(json.dumps(json_safe(res), indent=1, allow_nan=False))
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

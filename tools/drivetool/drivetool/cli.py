"""drivetool --port URL COMMAND ... : the command line of the drive's link.

Exit status: 0 ok, 1 refused by the firmware (the reason printed), 2 usage
or unknown name, 3 no answer. See tools/drivetool/README.md."""
import argparse
import csv
import json
import math
import re
import sys
import time

from . import codec
from .drive import FAULTS, STATES, Drive, LinkError, Refused, UsageError

STATUS_VARS = ["state", "fault", "flags", "speed_est_rpm", "speed_ref_rpm", "te_ref_Nm", "te_est_Nm",
               "id_meas_A", "iq_meas_A", "method", "mode", "cmd_error", "ticks",
               "link_err_crc", "link_err_framing", "link_err_overrun", "link_stream_dropped"]
CAPTURE_POLL_S = 0.05
# the commissioning (firmware/commission/commission.h): comm_result codes, stage names, and the
# measured values as link variables -> drive_sil's OUT.ini keys in [controller]
COMM_NONE, COMM_RUNNING, COMM_DONE, COMM_REFUSED = range(4)
COMM_STAGES = ["NONE", "R", "L", "ENCODER", "SPIN", "DONE", "WIRING"]
COMM_KEYS = ["R_ohm", "L_H", "psif_Wb", "pole_pairs", "J_kgm2", "B_Nms", "encoder_offset_el_rad",
             "speed_kp_Nms_rad", "speed_ki_Nm_rad", "deadtime_s", "device_drop_V", "untold_deadtime_s"]
COMM_POLL_S = 0.1


class Usage(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise Usage(message)


def _emit(args, obj, text):
    if args.json:
        print(json.dumps(obj))
    elif text is not None:
        print(text)


def _fmt(v):
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def cmd_status(d, args):
    v = d.get(*[n for n in STATUS_VARS if n in d.by_name])
    v["state_name"] = STATES[v["state"]] if v["state"] < len(STATES) else str(v["state"])
    v["fault_name"] = FAULTS[v["fault"]] if v["fault"] < len(FAULTS) else str(v["fault"])
    text = (f"state {v['state_name']}  fault {v['fault_name']}  speed_est_rpm {v['speed_est_rpm']:.1f}  "
            f"speed_ref_rpm {v['speed_ref_rpm']:.1f}  te_est_Nm {v['te_est_Nm']:.3f}  iq_meas_A {v['iq_meas_A']:.3f}\n"
            f"link errors: crc {v['link_err_crc']}, framing {v['link_err_framing']}, "
            f"overrun {v['link_err_overrun']}, stream dropped {v['link_stream_dropped']}  "
            f"(firmware {d.info['firmware']}, {d.info['baud']} baud)")
    _emit(args, v, text)


def cmd_list(d, args):
    rows = [v.to_dict() for v in d.vars]
    text = "\n".join(f"{r['name']:<22} {r['type']:<4} {r['access']:<11} [{_fmt(r['min'])}, {_fmt(r['max'])}] "
                     f"{r['unit']:<6} capture LSB {_fmt(r['scale'])}" for r in rows)
    _emit(args, rows, text)


def cmd_get(d, args):
    v = d.get(*args.names)
    _emit(args, v, "\n".join(f"{k} {_fmt(x)}" for k, x in v.items()))


def _parse_assign(s):
    if "=" not in s:
        raise UsageError(f"'{s}': expected NAME=VALUE")
    name, val = s.split("=", 1)
    try:
        return name.strip(), float(val)
    except ValueError:
        raise UsageError(f"'{s}': {val!r} is not a number") from None


def cmd_set(d, args):
    pairs = [_parse_assign(s) for s in args.assignments]
    for name, _ in pairs:
        d.var(name)                      # every name known before anything is written
    for name, val in pairs:
        d.set(name, val)
    _emit(args, {n: v for n, v in pairs}, None)


def _action(act):
    def run(d, args):
        d.action(act)
        _emit(args, {"ok": True}, None)
    return run


def cmd_commission(d, args):
    """Start the commissioning (the drive stopped), wait for its end, print and write the values."""
    st = d.get("state")["state"]
    if st not in (0, 1):
        raise Refused(f"commission: the drive is {STATES[st] if st < len(STATES) else st}; stop it first "
                      "(drivetool stop, or reset-fault)")
    d.action(codec.ACT_COMMISSION)
    deadline = time.monotonic() + args.wait
    seen = False                                  # the commissioning (or its calibration) has begun
    while True:
        v = d.get("state", "fault", "comm_result", "comm_stage")
        seen = seen or v["comm_result"] == COMM_RUNNING or v["state"] not in (0, 1)
        if v["comm_result"] in (COMM_DONE, COMM_REFUSED) and seen:
            break
        if seen and v["state"] in (0, 1) and v["comm_result"] == COMM_NONE:
            raise Refused("commission: the drive stopped before the commissioning ended")
        if time.monotonic() > deadline:
            raise Refused(f"commission: not finished within {args.wait:g} s (--wait)")
        time.sleep(COMM_POLL_S)
    stage = COMM_STAGES[v["comm_stage"]] if v["comm_stage"] < len(COMM_STAGES) else str(v["comm_stage"])
    if v["comm_result"] == COMM_REFUSED:
        fault = FAULTS[v["fault"]] if v["fault"] < len(FAULTS) else str(v["fault"])
        raise Refused(f"commission refused: {fault} in stage {stage} (drivetool reset-fault, then fix and retry)")
    vals = d.get(*["comm_" + k for k in COMM_KEYS])
    res = {k: vals["comm_" + k] for k in COMM_KEYS}
    if args.ini:
        with open(args.ini, "w") as f:
            f.write("; measured by drivetool commission (the drive's commissioning); not stored on the board\n"
                    "[controller]\n")
            for k, x in res.items():
                f.write(f"{k} = {_fmt(x)}\n")
            # R is measured: no step 1, R tracked in service (drive_sil's OUT.ini says the same)
            f.write("\n[identify]\nmode = trusted\n")
    _emit(args, res, " ".join(f"{k}={_fmt(x)}" for k, x in res.items()) + (f" -> {args.ini}" if args.ini else ""))


LEVEL_NAMES = {1: "PWM check", 2: "ADC check", 3: "encoder check", 4: "torque control", 5: "the full drive"}


def cmd_level(d, args):
    if args.n is not None:
        d.level(args.n)
    v = d.get("level", "level_next")
    _emit(args, v, f"level {v['level']} ({LEVEL_NAMES.get(v['level'], '?')}) at the last start; the next start "
                   f"runs level {v['level_next']} ({LEVEL_NAMES.get(v['level_next'], '?')})")


def _write_csv(path, names, t, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t_s"] + list(names))
        for ti, r in zip(t, rows):
            w.writerow([f"{ti:.9g}"] + [f"{x:.9g}" if isinstance(x, float) else x for x in r])


def _png(path, names, t, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(8, 2.2 * len(names)), squeeze=False)
    for k, name in enumerate(names):
        axes[k][0].plot(t, [r[k] for r in rows])
        axes[k][0].set_ylabel(name)
        axes[k][0].grid(True)
    axes[-1][0].set_xlabel("t_s")
    fig.tight_layout()
    fig.savefig(path)


def cmd_stream(d, args):
    ts = d.info["Ts_s"]
    dec = max(1, round(1.0 / (ts * args.rate)))
    need, budget = d.stream_set(args.names, dec)
    asked = 1.0 / (ts * dec)
    if not args.json:
        print(f"streaming {len(args.names)} variable(s) every {dec} periods ({asked:.1f} Hz): "
              f"{need} B/s of the link's {budget} B/s", file=sys.stderr)
    t0 = time.monotonic()
    d.poll(args.duration)
    elapsed = time.monotonic() - t0
    rows = d.stream_rows
    d.stream_set([], 1)
    got = len(rows) / elapsed if elapsed > 0 else 0.0
    if args.csv:
        _write_csv(args.csv, args.names, [idx * ts for idx, _ in rows], [r for _, r in rows])
    _emit(args, {"rows": len(rows), "rate_asked_hz": asked, "rate_got_hz": got, "need_Bps": need,
                 "budget_Bps": budget},
          f"got {len(rows)} rows in {elapsed:.2f} s: {got:.1f} Hz (asked {asked:.1f} Hz)")


TRIG_RE = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*([<>])\s*([-+0-9.eE]+)\s*$")


def _parse_trigger(s):
    if s in ("fault", "state", "forced", "now"):
        return {"fault": codec.TRIG_FAULT, "state": codec.TRIG_STATE}.get(s, codec.TRIG_FORCED), None, 0.0
    m = TRIG_RE.match(s)
    if not m:
        raise UsageError(f"--trigger '{s}': expected NAME>VALUE, NAME<VALUE, fault, state or forced")
    try:
        level = float(m.group(3))
    except ValueError:
        raise UsageError(f"--trigger '{s}': {m.group(3)!r} is not a number") from None
    return (codec.TRIG_ABOVE if m.group(2) == ">" else codec.TRIG_BELOW), m.group(1), level


def cmd_capture(d, args):
    trig, tname, level = _parse_trigger(args.trigger)
    d.capture_arm(args.names, trig, tname, level, args.hyst, args.pre, args.samples, args.decimate)
    deadline = time.monotonic() + args.wait
    while True:
        st = d.capture_status()
        if st["state"] == codec.CAP_DONE:
            break
        if time.monotonic() > deadline:
            raise Refused(f"capture: no trigger within {args.wait:g} s (--wait)")
        time.sleep(CAPTURE_POLL_S)
    t, rows = d.capture_read(st)
    if args.csv:
        _write_csv(args.csv, args.names, t, rows)
    if args.png:
        _png(args.png, args.names, t, rows)
    ts = d.info["Ts_s"]
    _emit(args, {"rows": len(rows), "trigger_t_s": st["trigger_index"] * ts, "first_t_s": st["first_index"] * ts,
                 "lsb": {n: (None if f == codec.CAP_F32 else lsb)
                         for n, (_i, lsb), f in zip(args.names, st["channels"], st["formats"])},
                 "format": {n: ("float32" if f == codec.CAP_F32 else "int16")
                            for n, f in zip(args.names, st["formats"])}},
          f"captured {len(rows)} rows, trigger at t = {st['trigger_index'] * ts:.6f} s"
          + (f" -> {args.csv}" if args.csv else ""))


def cmd_plot(d, args):
    import matplotlib.pyplot as plt
    ts = d.info["Ts_s"]
    dec = max(1, round(1.0 / (ts * args.rate)))
    d.stream_set(args.names, dec)
    fig, axes = plt.subplots(len(args.names), 1, sharex=True, squeeze=False)
    lines = [axes[k][0].plot([], [])[0] for k in range(len(args.names))]
    for k, n in enumerate(args.names):
        axes[k][0].set_ylabel(n)
    axes[-1][0].set_xlabel("t [s]")
    plt.ion()
    plt.show()
    frames = 0
    end = time.monotonic() + args.duration if args.duration > 0 else float("inf")
    try:
        while plt.fignum_exists(fig.number) and time.monotonic() < end and (args.frames <= 0 or frames < args.frames):
            d.poll(0.1)
            rows = d.stream_rows[-int(args.window / (ts * dec)):]
            if rows:
                t = [i * ts for i, _ in rows]
                for k, line in enumerate(lines):
                    line.set_data(t, [r[k] for _, r in rows])
                    axes[k][0].relim()
                    axes[k][0].autoscale_view()
            frames += 1
            plt.pause(0.05)
    except KeyboardInterrupt:
        pass
    got = list(d.stream_rows)
    d.stream_set([], 1)
    shown = got[-int(args.window / (ts * dec)):]
    if args.png:
        fig.savefig(args.png, dpi=80)
    _emit(args, {"frames": frames, "rows": len(got), "rows_shown": len(shown),
                 "t_s": [shown[0][0] * ts, shown[-1][0] * ts] if shown else None},
          f"{frames} frames, {len(got)} rows" + (f" -> {args.png}" if args.png else ""))


def cmd_backup(d, args):
    names = [v.name for v in d.vars if v.access != codec.ACC_READ]
    vals = d.get(*names)
    with open(args.file, "w") as f:
        json.dump(vals, f, indent=1)
        f.write("\n")
    _emit(args, vals, f"{len(vals)} writable variables -> {args.file}")


def cmd_restore(d, args):
    try:
        with open(args.file) as f:
            vals = json.load(f)
    except (OSError, ValueError) as e:
        raise UsageError(f"{args.file}: {e}") from None
    if not isinstance(vals, dict):
        raise UsageError(f"{args.file}: expected an object of NAME: VALUE")
    for name, val in vals.items():
        if d.var(name).access == codec.ACC_READ:
            raise UsageError(f"{args.file}: {name} is read-only")
        if not isinstance(val, (int, float)) or isinstance(val, bool) or not math.isfinite(val):
            raise UsageError(f"{args.file}: {name} is not a finite number")
    now = d.get(*vals)
    # only what differs is written: a write-when-stopped variable that is already right passes while running
    changed = {n: v for n, v in vals.items() if now[n] != v}
    for name, val in changed.items():
        d.set(name, val)
    _emit(args, changed, f"{len(changed)} of {len(vals)} variables restored from {args.file}")


def build_parser():
    p = Parser(prog="drivetool", description="Talk to the drive over its link (firmware/link/link_protocol.md). "
               "Exit status: 0 ok, 1 refused by the firmware, 2 usage or unknown name, 3 no answer.")
    p.add_argument("--port", required=True, help="serial device, socket://127.0.0.1:PORT (drive_sil --link) or loop://")
    p.add_argument("--baud", type=int, default=115200)
    p.add_argument("--timeout", type=float, default=2.0, help="seconds to keep trying to open the port")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--no-cache", action="store_true", help="list the variable table again")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=Parser)
    sub.add_parser("status").set_defaults(fn=cmd_status)
    sub.add_parser("list").set_defaults(fn=cmd_list)
    s = sub.add_parser("get")
    s.add_argument("names", nargs="+")
    s.set_defaults(fn=cmd_get)
    s = sub.add_parser("set")
    s.add_argument("assignments", nargs="+", metavar="NAME=VALUE")
    s.set_defaults(fn=cmd_set)
    sub.add_parser("start").set_defaults(fn=_action(codec.ACT_START))
    sub.add_parser("stop").set_defaults(fn=_action(codec.ACT_STOP))
    sub.add_parser("reset-fault").set_defaults(fn=_action(codec.ACT_FAULT_RESET))
    sub.add_parser("quit", help="SIL: stop and end drive_sil").set_defaults(fn=_action(codec.ACT_QUIT))
    s = sub.add_parser("commission", help="measure the motor (the drive stopped), print the values")
    s.add_argument("--ini", help="write the values as a [controller] section (drive_sil's OUT.ini keys)")
    s.add_argument("--wait", type=float, default=120.0, help="seconds to wait for the end")
    s.set_defaults(fn=cmd_commission)


    s = sub.add_parser("level", help="the build level the next start runs (without N: show it)")
    s.add_argument("n", nargs="?", type=int, choices=range(1, 6), metavar="N",
                   help="1 PWM, 2 ADC, 3 encoder check, 4 torque control, 5 the drive")
    s.set_defaults(fn=cmd_level)
    s = sub.add_parser("stream")
    s.add_argument("names", nargs="+")
    s.add_argument("--rate", type=float, default=100.0, help="rows per second asked for [Hz]")
    s.add_argument("--duration", type=float, default=1.0, help="seconds")
    s.add_argument("--csv")
    s.set_defaults(fn=cmd_stream)
    s = sub.add_parser("capture")
    s.add_argument("names", nargs="+")
    s.add_argument("--trigger", default="forced", help="'NAME>VALUE', 'NAME<VALUE', fault, state or forced")
    s.add_argument("--pre", type=int, default=0, help="rows before the trigger (part of --samples)")
    s.add_argument("--samples", type=int, default=1000, help="rows in all")
    s.add_argument("--decimate", type=int, default=1, help="a row every K periods")
    s.add_argument("--hyst", type=float, default=0.0, help="re-arm only after crossing back by this much")
    s.add_argument("--wait", type=float, default=60.0, help="seconds to wait for the trigger")
    s.add_argument("--csv")
    s.add_argument("--png")
    s.set_defaults(fn=cmd_capture)
    s = sub.add_parser("plot")
    s.add_argument("names", nargs="+")
    s.add_argument("--rate", type=float, default=50.0)
    s.add_argument("--window", type=float, default=5.0, help="seconds shown")
    s.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds (0: until closed)")
    s.add_argument("--frames", type=int, default=0, help="stop after this many redraws (0: until closed)")
    s.add_argument("--png", help="save the last frame (with MPLBACKEND=Agg: a headless plot)")
    s.set_defaults(fn=cmd_plot)
    s = sub.add_parser("backup")
    s.add_argument("file")
    s.set_defaults(fn=cmd_backup)
    s = sub.add_parser("restore")
    s.add_argument("file")
    s.set_defaults(fn=cmd_restore)
    return p


def main(argv=None):
    try:
        args = build_parser().parse_args(argv)
    except Usage as e:
        print(f"drivetool: {e}", file=sys.stderr)
        return 2
    try:
        with Drive(args.port, timeout=args.timeout, baud=args.baud, cache=not args.no_cache,
                   warn=lambda m: print(f"drivetool: warning: {m}", file=sys.stderr)) as d:
            args.fn(d, args)
    except LinkError as e:
        print(f"drivetool: {e}", file=sys.stderr)
        return e.code
    except OSError as e:
        print(f"drivetool: {e}", file=sys.stderr)
        return 3
    return 0

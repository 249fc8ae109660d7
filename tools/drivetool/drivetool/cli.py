"""drivetool [--port URL] COMMAND ... : the command line of the drive's link.

Exit status: 0 ok, 1 refused by the firmware (the reason printed), 2 usage
or unknown name, 3 no answer, 130 interrupted (Ctrl-C). See
tools/drivetool/README.md."""
import argparse
import configparser
import csv
import json
import math
import os
import re
import struct
import sys
import time

from . import codec
from .drive import (CMD_ERR_FAULTED, CMD_ERR_NOT_STOPPED, COMM_STAGES, FAULTS, RETRIES, SAVE_WAIT_S, WARNING_BITS,
                    Drive, LinkError, NoAnswer, Refused, UsageError, bits_names, enum_name, show)

PORT_ENV = "DRIVETOOL_PORT"
EXIT_INTERRUPTED = 130          # 128 + SIGINT, as a shell reports it
STATUS_VARS = ["state", "fault", "flags", "speed_est_rpm", "speed_ref_rpm", "te_ref_Nm", "te_est_Nm",
               "id_meas_A", "iq_meas_A", "vdc_V", "method", "method_ran", "hold_reason", "mode", "cmd_error",
               "ticks", "host_timeout_s", "nv_status", "link_err_crc", "link_err_framing", "link_err_overrun",
               "link_stream_dropped"]
CAPTURE_POLL_S = 0.05
# the commissioning (firmware/commission/commission.h): comm_result codes, and the measured values as
# link variables -> drive_sil's OUT.ini keys in [controller]
COMM_NONE, COMM_RUNNING, COMM_DONE, COMM_REFUSED = range(4)
COMM_KEYS = ["R_ohm", "L_H", "psif_Wb", "pole_pairs", "J_kgm2", "B_Nms", "encoder_offset_el_rad",
             "speed_kp_Nms_rad", "speed_ki_Nm_rad", "deadtime_s", "device_drop_V", "untold_deadtime_s"]
COMM_POLL_S = 0.1
STOPPED = (0, 1)                # INIT, IDLE
STATE_FAULT = 6
# reset-fault: the drive takes the request at its next ISR call; its outcome read after this many
RESET_TAKEN_PERIODS = 2
RESET_WAIT_S = 5.0              # ... or give up (the ISR does not run)
RESET_POLL_S = 0.02
INI_SECTION = "controller"      # backup's section: drive_sil's [controller] keys


class Usage(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise Usage(message)


class Help(argparse.RawDescriptionHelpFormatter):
    """Each option's default in its help (one that has a value); descriptions as written."""

    def _get_help_string(self, action):
        text = action.help or ""
        d = action.default
        shown = not (d is None or d is False or d is argparse.SUPPRESS) and action.option_strings
        return text + (" (default: %(default)s)" if shown and "%(default)" not in text else "")


def _emit(args, obj, text):
    if args.json:
        print(json.dumps(obj))
    elif text is not None:
        print(text)


def _fmt(v):
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def _note(msg):
    print(f"drivetool: {msg}", file=sys.stderr)


# ---- reading -------------------------------------------------------------------

def cmd_status(d, args):
    v = d.get(*[n for n in STATUS_VARS if n in d.by_name])
    v["state_name"] = enum_name("state", v["state"])
    v["fault_name"] = enum_name("fault", v["fault"])
    for n in ("method", "method_ran", "mode"):
        if n in v:
            v[n + "_name"] = enum_name(n, v[n])
    if "hold_reason" in v:
        v["hold_reason_names"] = bits_names("hold_reason", v["hold_reason"]).split()[1:]
    warn = v["flags"] & WARNING_BITS
    v["warnings"] = bits_names("flags", warn).split()[1:]
    def z(x):
        return x + 0.0   # no "-0.0": a reading rounded to zero prints as zero
    lines = [f"state {v['state_name']}  fault {v['fault_name']}  speed_est_rpm {z(round(v['speed_est_rpm'], 1)):.1f}  "
             f"speed_ref_rpm {z(round(v['speed_ref_rpm'], 1)):.1f}  te_est_Nm {z(round(v['te_est_Nm'], 3)):.3f}  "
             f"id_meas_A {z(round(v['id_meas_A'], 3)):.3f}  iq_meas_A {z(round(v['iq_meas_A'], 3)):.3f}"
             + (f"  vdc_V {v['vdc_V']:.1f}" if "vdc_V" in v else "")]
    if "method_ran" in v:
        lines.append(f"method {v['method_name']}, ran {v['method_ran_name']} "
                     f"(hold_reason {bits_names('hold_reason', v['hold_reason'])}), mode {v['mode_name']}")
    if "host_timeout_s" in v:
        lines.append("host timeout " + (f"{v['host_timeout_s']:g} s" if v["host_timeout_s"] > 0 else "off")
                     + ("; warnings " + " ".join(v["warnings"]) if v["warnings"] else ""))
    if "nv_status" in v:
        v["nv_status_name"] = enum_name("nv_status", v["nv_status"])
        lines.append(f"parameter store {v['nv_status_name']}")
    lines.append(f"link errors: crc {v['link_err_crc']}, framing {v['link_err_framing']}, "
                 f"overrun {v['link_err_overrun']}, stream dropped {v['link_stream_dropped']}  "
                 f"(firmware {d.info['firmware']}, {d.info['baud']} baud)")
    _emit(args, v, "\n".join(lines))


def cmd_list(d, args):
    rows = [v.to_dict() for v in d.vars]
    for r, v in zip(rows, d.vars):
        r["capture_lsb"] = None if v.fmt == codec.CAP_F32 else v.scale
    cells = [[r["name"], r["type"], r["access"] + (" param" if r["parameter"] else ""),
              f"[{_fmt(r['min'])}, {_fmt(r['max'])}]", r["unit"] or "-",
              "float32" if r["capture"] == "float32" else f"int16, LSB {_fmt(r['scale'])}"] for r in rows]
    head = ["name", "type", "access", "limits", "unit", "capture"]
    width = [max(len(c[k]) for c in cells + [head]) for k in range(len(head))]
    text = "\n".join("  ".join(c[k].ljust(width[k]) for k in range(len(head))).rstrip() for c in [head] + cells)
    _emit(args, rows, text)


def cmd_get(d, args):
    v = d.get(*args.names)
    _emit(args, v, "\n".join(f"{k} {show(k, x)}" for k, x in v.items()))


def _parse_assign(d, s):
    if "=" not in s:
        raise UsageError(f"'{s}': expected NAME=VALUE")
    name, val = s.split("=", 1)
    name = name.strip()
    return name, d.var(name).parse(val.strip())


def _check_param_range(d, name, val):
    """A parameter's value within the limits the drive checks it against: Refused naming them."""
    v = d.var(name)
    if v.param and not v.lo <= val <= v.hi:
        raise Refused(f"{name}={val:g} refused: outside {name}'s limits {v.lo:.6g} .. {v.hi:.6g} {v.unit}".rstrip())


def cmd_set(d, args):
    pairs = [_parse_assign(d, s) for s in args.assignments]   # every name and value checked first
    for name, val in pairs:
        _check_param_range(d, name, val)
    for name, val in pairs:
        d.set(name, val)
    _emit(args, {n: v for n, v in pairs}, None)


# ---- actions: an action that does nothing says why -----------------------------

def _refusal_text(d, e, what):
    """The reason of an action's refusal, naming the fault or the state."""
    v = d.get("state", "fault")
    if e.err == CMD_ERR_FAULTED:
        return f"{what} refused: fault {enum_name('fault', v['fault'])} is latched (drivetool reset-fault first)"
    if e.err == CMD_ERR_NOT_STOPPED:
        return f"{what} refused: the drive is {enum_name('state', v['state'])}, not stopped (drivetool stop first)"
    return f"{what} refused: {e}"


def cmd_start(d, args):
    try:
        d.action(codec.ACT_START)
    except Refused as e:
        raise Refused(_refusal_text(d, e, "start")) from None
    _emit(args, {"ok": True}, None)


def _action(act):
    def run(d, args):
        d.action(act)
        _emit(args, {"ok": True}, None)
    return run


def cmd_reset_fault(d, args):
    """Reset a latched fault; exit 1 naming it when its cause is still there."""
    v = d.get("state", "fault")
    if v["state"] != STATE_FAULT:
        _note(f"reset-fault: no fault latched (the drive is {enum_name('state', v['state'])}): nothing to reset")
        _emit(args, {"ok": True, "reset": False}, None)
        return
    fault = v["fault"]
    d.action(codec.ACT_FAULT_RESET)
    t0 = d.get("ticks")["ticks"]
    deadline = time.monotonic() + RESET_WAIT_S
    while True:             # the drive's next ISR call takes the request
        v = d.get("ticks", "state", "fault", "fault_present")
        if (v["ticks"] - t0) % 2 ** 32 >= RESET_TAKEN_PERIODS:
            break
        if time.monotonic() > deadline:
            raise NoAnswer(f"reset-fault: the drive's period count did not move in {RESET_WAIT_S:g} s")
        time.sleep(RESET_POLL_S)
    if v["state"] == STATE_FAULT:
        present = enum_name("fault", v["fault_present"])
        raise Refused(f"reset-fault refused: fault {enum_name('fault', v['fault'])} stays latched: its cause is "
                      f"still there ({present} fails now)")
    _emit(args, {"ok": True, "reset": True, "fault": fault}, None)


def cmd_commission(d, args):
    """Start the commissioning (the drive stopped), wait for its end, print and write the values."""
    try:
        d.action(codec.ACT_COMMISSION)
    except Refused as e:
        raise Refused(_refusal_text(d, e, "commission")) from None
    deadline = time.monotonic() + args.wait
    seen = False                                  # the commissioning (or its calibration) has begun
    while True:
        v = d.get("state", "fault", "comm_result", "comm_stage")
        seen = seen or v["comm_result"] == COMM_RUNNING or v["state"] not in STOPPED
        if v["comm_result"] in (COMM_DONE, COMM_REFUSED) and seen:
            break
        if seen and v["state"] in STOPPED and v["comm_result"] == COMM_NONE:
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
                    f"[{INI_SECTION}]\n")
            for k, x in res.items():
                f.write(f"{k} = {_fmt(x)}\n")
            # R is measured: no step 1, R tracked in service (drive_sil's OUT.ini says the same)
            f.write("\n[identify]\nmode = trusted\n")
    _emit(args, res, " ".join(f"{k}={_fmt(x)}" for k, x in res.items()) + (f" -> {args.ini}" if args.ini else ""))


def cmd_save(d, args):
    """The drive's parameters into its store (flash sector B; drive_sil --nv FILE), the drive stopped."""
    try:
        d.save(args.wait)
    except Refused as e:
        raise Refused(_refusal_text(d, e, "save") if e.err is not None else str(e)) from None
    n = sum(1 for v in d.vars if v.param)
    _emit(args, {"ok": True, "saved": n}, f"{n} parameters saved: the next start takes them (nv_status VALID)")


LEVEL_NAMES = {1: "PWM check", 2: "ADC check", 3: "encoder check", 4: "torque control", 5: "the full drive"}


def cmd_level(d, args):
    if args.n is not None:
        d.level(args.n)
    v = d.get("level", "level_next")
    _emit(args, v, f"level {v['level']} ({LEVEL_NAMES.get(v['level'], '?')}) at the last start; the next start "
                   f"runs level {v['level_next']} ({LEVEL_NAMES.get(v['level_next'], '?')})")


# ---- stream, capture, plot -----------------------------------------------------

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


def _stop_stream(d):
    """The stream off, as far as the link still answers (an interrupted command ends anyway)."""
    try:
        d.stream_set([], 1)
    except LinkError:
        pass


def cmd_stream(d, args):
    ts = d.info["Ts_s"]
    dec = max(1, round(1.0 / (ts * args.rate)))
    need, budget = d.stream_set(args.names, dec)
    asked = 1.0 / (ts * dec)
    if not args.json:
        print(f"streaming {len(args.names)} variable(s) every {dec} periods ({asked:.1f} Hz): "
              f"{need} B/s of the link's {budget} B/s", file=sys.stderr, flush=True)
    t0 = time.monotonic()
    try:
        d.poll(args.duration)
    finally:                                  # Ctrl-C too: the drive stops streaming
        rows = list(d.stream_rows)
        _stop_stream(d)
    elapsed = time.monotonic() - t0
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


def _capture_arm(d, args):
    if not args.names:
        raise UsageError("capture: name 1 to 4 variables to capture")
    trig, tname, level = _parse_trigger(args.trigger)
    d.capture_arm(args.names, trig, tname, level, args.hyst, args.pre, args.samples, args.decimate)


def _capture_fetch(d, args):
    """Wait for the armed capture, upload it, write and report it (the names from its channel ids)."""
    deadline = time.monotonic() + args.wait
    while True:
        st = d.capture_status()
        if st["state"] == codec.CAP_DONE:
            break
        if st["state"] == codec.CAP_IDLE:
            raise Refused("capture --fetch: no capture armed (capture --arm first)")
        if time.monotonic() > deadline:
            raise Refused(f"capture: no trigger within {args.wait:g} s (--wait)")
        time.sleep(CAPTURE_POLL_S)
    names = [d.vars[vid].name for vid, _lsb in st["channels"]]
    t, rows = d.capture_read(st)
    if args.csv:
        _write_csv(args.csv, names, t, rows)
    if args.png:
        _png(args.png, names, t, rows)
    ts = d.info["Ts_s"]
    _emit(args, {"rows": len(rows), "trigger_t_s": st["trigger_index"] * ts, "first_t_s": st["first_index"] * ts,
                 "names": names,
                 "lsb": {n: (None if f == codec.CAP_F32 else lsb)
                         for n, (_i, lsb), f in zip(names, st["channels"], st["formats"])},
                 "format": {n: ("float32" if f == codec.CAP_F32 else "int16") for n, f in zip(names, st["formats"])}},
          f"captured {len(rows)} rows, trigger at t = {st['trigger_index'] * ts:.6f} s"
          + (f" -> {args.csv}" if args.csv else ""))


def cmd_capture(d, args):
    if args.arm and args.fetch:
        raise UsageError("capture: --arm or --fetch, not both (neither: arm, wait and fetch at once)")
    if args.fetch and args.names:
        raise UsageError("capture --fetch takes no names: the capture armed says its channels")
    if not args.fetch:
        _capture_arm(d, args)
    if args.arm:
        _emit(args, {"armed": True}, f"armed: {', '.join(args.names)} (drivetool capture --fetch collects it)")
        return
    _capture_fetch(d, args)


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
        pass                                  # the plot's own end: the last frame is kept
    got = list(d.stream_rows)
    _stop_stream(d)
    shown = got[-int(args.window / (ts * dec)):]
    if args.png:
        fig.savefig(args.png, dpi=80)
    _emit(args, {"frames": frames, "rows": len(got), "rows_shown": len(shown),
                 "t_s": [shown[0][0] * ts, shown[-1][0] * ts] if shown else None},
          f"{frames} frames, {len(got)} rows" + (f" -> {args.png}" if args.png else ""))


# ---- parameters: backup and restore ----------------------------------------------

def _same_f32(a, b):
    """a and b the same value once on the link (float32, its bits)."""
    return struct.pack("<f", float(a)) == struct.pack("<f", float(b))


def cmd_backup(d, args):
    """Every parameter of the drive as an INI [controller] section drive_sil accepts (or, for a
    FILE.json, the writable variables as JSON: drivetool's earlier backup)."""
    if args.file.endswith(".json"):
        names = [v.name for v in d.vars if v.access != codec.ACC_READ]
        vals = d.get(*names)
        with open(args.file, "w") as f:
            json.dump(vals, f, indent=1)
            f.write("\n")
        _emit(args, vals, f"{len(vals)} writable variables -> {args.file}")
        return
    names = [v.name for v in d.vars if v.param]
    if not names:
        raise Refused("backup: this drive has no parameters on its link (an older firmware: FILE.json)")
    vals = d.get(*names)
    with open(args.file, "w") as f:
        f.write(f"; the drive's parameters, by drivetool backup ({d.info['firmware']}); drivetool restore, or\n"
                f"; drive_sil --scenario X.ini with this section in X.ini\n[{INI_SECTION}]\n")
        for n in names:
            f.write(f"{n} = {vals[n]:.9g}\n" if isinstance(vals[n], float) else f"{n} = {vals[n]}\n")
    _emit(args, vals, f"{len(vals)} parameters -> {args.file}")


def _read_restore(d, path):
    """{name: value} from a backup: an INI [controller] section of the drive's parameters (other
    sections, e.g. a whole scenario's, left alone), or drivetool's JSON of writable variables."""
    try:
        with open(path) as f:
            text = f.read()
    except OSError as e:
        raise UsageError(f"{path}: {e}") from None
    if text.lstrip().startswith("{"):
        try:
            vals = json.loads(text)
        except ValueError as e:
            raise UsageError(f"{path}: {e}") from None
        if not isinstance(vals, dict):
            raise UsageError(f"{path}: expected an object of NAME: VALUE")
        out = {}
        for name, val in vals.items():
            if d.var(name).access == codec.ACC_READ:
                raise UsageError(f"{path}: {name} is read-only")
            if not isinstance(val, (int, float)) or isinstance(val, bool) or not math.isfinite(val):
                raise UsageError(f"{path}: {name} is not a finite number")
            out[name] = d.var(name).check(val)
        return out
    ini = configparser.ConfigParser(inline_comment_prefixes=(";", "#"), interpolation=None)
    ini.optionxform = str
    try:
        ini.read_string(text, source=path)
    except configparser.Error as e:
        raise UsageError(f"{path}: {e}") from None
    if not ini.has_section(INI_SECTION):
        raise UsageError(f"{path}: no [{INI_SECTION}] section")
    out = {}
    for name, text_val in ini.items(INI_SECTION):
        v = d.by_name.get(name)
        if v is None or not v.param:
            raise UsageError(f"{path}: [{INI_SECTION}] {name}: not a parameter of this drive's link "
                             "(drivetool list marks them 'param')")
        x = v.parse(text_val)
        if not (v.lo <= x <= v.hi):
            raise UsageError(f"{path}: [{INI_SECTION}] {name} = {text_val}: outside its limits "
                             f"{v.lo:.6g} .. {v.hi:.6g} {v.unit}".rstrip())
        out[name] = x
    return out


def cmd_restore(d, args):
    """Write a backup back, all or nothing: every name and value checked first, only what differs as
    float32 written, and the ones written put back when one is refused."""
    vals = _read_restore(d, args.file)
    now = d.get(*vals)
    changed = {n: v for n, v in vals.items() if not _same_f32(now[n], v)}
    done = []
    try:
        for name, val in changed.items():
            d.set(name, val)
            done.append(name)
    except LinkError as e:
        undo_failed = []
        for name in reversed(done):
            try:
                d.set(name, now[name])
            except LinkError:
                undo_failed.append(name)
        left = (f"; could not put back {', '.join(undo_failed)}" if undo_failed
                else f"; the {len(done)} written before it put back" if done else "")
        raise type(e)(f"restore: nothing kept: {e}{left}") from None
    _emit(args, changed, f"{len(changed)} of {len(vals)} values restored from {args.file}"
                         + (f" ({len(vals) - len(changed)} already equal)" if len(vals) > len(changed) else ""))


# ---- the command line ------------------------------------------------------------

def _sub(sub, name, fn, text, json_parent):
    s = sub.add_parser(name, help=text, description=text, parents=[json_parent], formatter_class=Help)
    s.set_defaults(fn=fn)
    return s


def _add_link_options(p):
    """The options before COMMAND: the port, the line and the output; build_parser's first part."""
    p.add_argument("--port", default=os.environ.get(PORT_ENV),
                   help=f"serial device, socket://127.0.0.1:PORT (drive_sil --link) or loop:// "
                        f"(default: ${PORT_ENV})")
    p.add_argument("--baud", type=int, default=115200, help="the line's rate [bit/s]")
    p.add_argument("--timeout", type=float, default=2.0,
                   help="seconds to keep trying to open the port (and a link held by another client)")
    p.add_argument("--retries", type=int, default=RETRIES,
                   help="tries of a request before giving up; a capture's upload gives up after this many "
                        "reply times with no reply at all")
    p.add_argument("--json", action="store_true", help="print the result as JSON (numbers, not names)")
    p.add_argument("--no-cache", action="store_true", help="list the variable table again")


def _json_parent():
    """--json after COMMAND too: a parent of every command's parser, which leaves the global one alone
    unless given."""
    js = Parser(add_help=False)
    js.add_argument("--json", action="store_true", default=argparse.SUPPRESS,
                    help="print the result as JSON (numbers, not names)")
    return js


def _add_reading_commands(sub, js):
    """status, list, get and set (in the help in this order, before the actions)."""
    _sub(sub, "status", cmd_status, "state, fault, speed, torque, currents, bus, the method that ran and why "
         "(hold_reason), the host timeout, warnings, the link's error counts", js)
    _sub(sub, "list", cmd_list, "the variable table: name, type, access (r, rw, rw-stopped; param: a parameter "
         "of the drive), limits, unit, capture format", js)
    s = _sub(sub, "get", cmd_get, "values (enumerations and bit sets by name; numbers with --json)", js)
    s.add_argument("names", nargs="+", metavar="NAME")
    s = _sub(sub, "set", cmd_set, "write values through the firmware's checks (an enumeration by name or number; "
             "an integer refuses a fraction); a refused value names the reason and is not applied", js)
    s.add_argument("assignments", nargs="+", metavar="NAME=VALUE")


def _add_action_commands(sub, js):
    """start, stop, reset-fault, quit, commission, save and level (in the help in this order)."""
    _sub(sub, "start", cmd_start, "start the drive (refused naming the fault when one is latched)", js)
    _sub(sub, "stop", _action(codec.ACT_STOP), "stop the drive (PWM off)", js)
    _sub(sub, "reset-fault", cmd_reset_fault, "reset a latched fault; refused naming it while its cause is "
         "still there", js)
    _sub(sub, "quit", _action(codec.ACT_QUIT), "SIL: stop and end drive_sil (the board only stops)", js)
    s = _sub(sub, "commission", cmd_commission, "measure the motor (the drive stopped), print the values "
             "(refused naming the state or the fault otherwise)", js)
    s.add_argument("--ini", help="write the values as a [controller] section (drive_sil's OUT.ini keys)")
    s.add_argument("--wait", type=float, default=120.0, help="seconds to wait for the end")
    s = _sub(sub, "save", cmd_save, "save the drive's parameters (backup's) in its store, read at every start "
             "(the drive stopped: refused naming the state otherwise)", js)
    s.add_argument("--wait", type=float, default=SAVE_WAIT_S, help="seconds to wait for the flash")
    s = _sub(sub, "level", cmd_level, "the build level the next start runs (without N: show it)", js)
    s.add_argument("n", nargs="?", type=int, choices=range(1, 6), metavar="N",
                   help="1 PWM, 2 ADC, 3 encoder check, 4 torque control, 5 the drive")


def _add_capture_command(sub, js):
    """capture: its names, modes (--arm, --fetch), trigger, depth and outputs."""
    s = _sub(sub, "capture", cmd_capture, "a triggered capture sampled in the control ISR: arm, wait, upload "
             "(--arm: only arm and return; --fetch: wait for the armed one and upload it)", js)
    s.add_argument("names", nargs="*", metavar="NAME", help="1 to 4 variables (none with --fetch)")
    s.add_argument("--arm", action="store_true", help="arm and return at once")
    s.add_argument("--fetch", action="store_true", help="wait for the armed capture and upload it")
    s.add_argument("--trigger", default="forced", help="'NAME>VALUE', 'NAME<VALUE', fault, state or forced")
    s.add_argument("--pre", type=int, default=0, help="rows before the trigger (part of --samples)")
    s.add_argument("--samples", type=int, default=1000, help="rows in all")
    s.add_argument("--decimate", type=int, default=1, help="a row every K periods")
    s.add_argument("--hyst", type=float, default=0.0, help="re-arm only after crossing back by this much")
    s.add_argument("--wait", type=float, default=60.0, help="seconds to wait for the trigger")
    s.add_argument("--csv", help="write the rows (t_s, then the names)")
    s.add_argument("--png", help="draw the channels")


def _add_recording_commands(sub, js):
    """stream, capture and plot (in the help in this order)."""
    s = _sub(sub, "stream", cmd_stream, "stream variables for a while (Ctrl-C stops it: exit 130)", js)
    s.add_argument("names", nargs="+", metavar="NAME")
    s.add_argument("--rate", type=float, default=100.0, help="rows per second asked for [Hz]")
    s.add_argument("--duration", type=float, default=1.0, help="seconds")
    s.add_argument("--csv", help="write the rows (t_s, then the names)")
    _add_capture_command(sub, js)
    s = _sub(sub, "plot", cmd_plot, "a live plot of a stream (matplotlib)", js)
    s.add_argument("names", nargs="+", metavar="NAME")
    s.add_argument("--rate", type=float, default=50.0, help="rows per second asked for [Hz]")
    s.add_argument("--window", type=float, default=5.0, help="seconds shown")
    s.add_argument("--duration", type=float, default=0.0, help="stop after this many seconds (0: until closed)")
    s.add_argument("--frames", type=int, default=0, help="stop after this many redraws (0: until closed)")
    s.add_argument("--png", help="save the last frame (with MPLBACKEND=Agg: a headless plot)")


def _add_backup_commands(sub, js):
    """backup and restore (the last in the help)."""
    s = _sub(sub, "backup", cmd_backup, "every parameter of the drive as an INI [controller] section drive_sil "
             "accepts (FILE.json: the writable variables as JSON)", js)
    s.add_argument("file", metavar="FILE")
    s = _sub(sub, "restore", cmd_restore, "write a backup back (an INI [controller] section, or drivetool's JSON), "
             "all or nothing: checked first, only what differs (as float32) written", js)
    s.add_argument("file", metavar="FILE")


def build_parser():
    """drivetool's command line: the link's options, then one command (main's first step)."""
    p = Parser(prog="drivetool", formatter_class=Help,
               description="Talk to the drive over its link (firmware/link/link_protocol.md). Exit status: 0 ok, "
                           "1 refused by the firmware, 2 usage or unknown name, 3 no answer, 130 interrupted.")
    _add_link_options(p)
    js = _json_parent()
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=Parser, metavar="COMMAND")
    _add_reading_commands(sub, js)
    _add_action_commands(sub, js)
    _add_recording_commands(sub, js)
    _add_backup_commands(sub, js)
    return p

def main(argv=None):
    try:
        args = build_parser().parse_args(argv)
        if not args.port:
            raise Usage(f"no port: give --port URL or set {PORT_ENV}")
    except Usage as e:
        print(f"drivetool: {e}", file=sys.stderr)
        return 2
    try:
        with Drive(args.port, timeout=args.timeout, baud=args.baud, retries=args.retries, cache=not args.no_cache,
                   warn=lambda m: print(f"drivetool: warning: {m}", file=sys.stderr)) as d:
            args.fn(d, args)
    except KeyboardInterrupt:
        print("drivetool: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:                     # the reader of stdout left (| head): nothing more to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except LinkError as e:
        print(f"drivetool: {e}", file=sys.stderr)
        return e.code
    except OSError as e:
        print(f"drivetool: {e}", file=sys.stderr)
        return 3
    return 0

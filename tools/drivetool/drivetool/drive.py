"""Drive: the host's API of the link (firmware/link/link_protocol.md).

    from drivetool import Drive
    with Drive("socket://127.0.0.1:5555") as d:
        print(d.get("speed_est_rpm"))
        d.set("speed_ref_rpm", 500)

Opens the port with pyserial's serial_for_url (a serial device,
socket://HOST:PORT, loop://), retrying for `timeout` seconds. Every request
is retried with the same sequence number when its reply does not come: the
drive answers a repeat from its reply cache, so a write or an action is
applied once. The variable table is cached by HELLO's hash."""
import json
import os
import struct
import time

from . import codec

CMD_ERRORS = {
    0: "ok",
    1: "method is neither conventional (0) nor proposed (1)",
    2: "proposed method refused: its observer configuration failed at init",
    3: "mode is not open loop (0), torque (1) or speed (2)",
    4: "speed reference not finite or beyond the drive's limit",
    5: "torque reference not finite or beyond the drive's limit",
    6: "open-loop voltage not finite or beyond the drive's limit",
    7: "proposed method refused: step 1 is off or refused R^ at this start",
    8: "level is not 1 .. 5",
}
STATES = ["INIT", "IDLE", "CALIBRATE", "ALIGN", "IDENTIFY_R", "RUN", "FAULT", "PWM_CHECK", "ADC_CHECK",
          "ENC_CHECK", "COMMISSION"]
FAULTS = ["NONE", "HW_TRIP", "OVERCURRENT", "NONFINITE_OUTPUT", "NONFINITE_SAMPLE", "OVERVOLTAGE",
          "UNDERVOLTAGE", "OVERSPEED", "ENCODER", "OVERRUN", "CURRENT_OFFSET", "CONFIG", "RSID_TOO_FEW",
          "RSID_NOT_STEADY", "RSID_DEGENERATE", "RSID_NON_FINITE", "RSID_OUT_OF_BAND", "OPEN_PHASE",
          "CURRENT_SENSOR", "ENCODER_LOST", "WATCHDOG_RESET", "FLASH_CRC", "ENCODER_DIRECTION", "POLE_PAIRS",
          "PHASE_ORDER", "RSID_D_AXIS", "COMM_TIMEOUT", "COMM_NO_ROTATION", "COMM_IMPLAUSIBLE",
          "BUS_CHARGED"]
ACCESS = {codec.ACC_READ: "r", codec.ACC_WRITE: "rw", codec.ACC_WRITE_STOPPED: "rw-stopped"}
TYPES = {codec.T_U16: "u16", codec.T_U32: "u32", codec.T_F32: "f32"}


class LinkError(Exception):
    """Base of the drive's errors; `code` is drivetool's exit status."""
    code = 1


class Refused(LinkError):
    """The firmware refused the request (the reason in the message)."""
    code = 1


class UsageError(LinkError):
    """Bad usage or an unknown variable name."""
    code = 2


class NoAnswer(LinkError):
    """No port, or no reply after the retries."""
    code = 3


class Var:
    def __init__(self, vid, name, unit, vtype, access, lo, hi, scale):
        self.id, self.name, self.unit, self.type, self.access = vid, name, unit, vtype, access
        self.lo, self.hi, self.scale = lo, hi, scale

    def to_dict(self):
        return {"id": self.id, "name": self.name, "unit": self.unit, "type": TYPES[self.type],
                "access": ACCESS[self.access], "min": self.lo, "max": self.hi, "scale": self.scale}

    def decode(self, b, i):
        """The value at b[i:], and the index after it."""
        if self.type == codec.T_U16:
            return struct.unpack_from("<H", b, i)[0], i + 2
        if self.type == codec.T_U32:
            return struct.unpack_from("<I", b, i)[0], i + 4
        return struct.unpack_from("<f", b, i)[0], i + 4


def _cache_dir():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "drivetool")


class Drive:
    def __init__(self, url, timeout=2.0, baud=115200, retries=6, cache=True, warn=None):
        self.url, self.baud, self.retries, self.use_cache = url, baud, retries, cache
        self.warn = warn or (lambda msg: None)
        self.rx = codec.Receiver()
        self.seq = 0
        self.stream_rows = []       # (period index, [values]) of unsolicited stream frames
        self.stream_ids = []
        self.events = []            # (state, fault, period index)
        self.port = self._open(url, timeout, baud)
        # a reply at the line's rate, with room for the drive's background loop
        self.reply_timeout = 0.15 + 2 * (codec.PAYLOAD_MAX + 8) * 10.0 / baud
        self.info = self.hello()
        self.vars = self._table()
        self.by_name = {v.name: v for v in self.vars}

    # ---- port ---------------------------------------------------------------
    @staticmethod
    def _open(url, timeout, baud):
        try:
            import serial  # pyserial
        except ImportError as e:  # pragma: no cover - the venv has it
            raise NoAnswer("pyserial is not installed (make drivetool)") from e
        deadline = time.monotonic() + timeout
        while True:
            try:
                return serial.serial_for_url(url, baudrate=baud, timeout=0.02)
            except (serial.SerialException, OSError, ValueError) as e:
                if time.monotonic() >= deadline:
                    raise NoAnswer(f"cannot open {url}: {e}") from e
                time.sleep(0.05)

    def close(self):
        self.port.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _take_unsolicited(self, ftype, payload):
        if ftype == codec.STREAM and len(payload) >= 4:
            idx = struct.unpack_from("<I", payload, 0)[0]
            vals, i = [], 4
            try:
                for vid in self.stream_ids:
                    v, i = self.vars[vid].decode(payload, i)
                    vals.append(v)
            except struct.error:
                return
            self.stream_rows.append((idx, vals))
        elif ftype == codec.EVENT and len(payload) >= 6:
            self.events.append((payload[0], payload[1], struct.unpack_from("<I", payload, 2)[0]))

    def poll(self, wait=0.0):
        """Read what has come (for up to `wait` s), keeping stream rows and events."""
        end = time.monotonic() + wait
        while True:
            data = self.port.read(max(1, self.port.in_waiting))
            for ftype, _seq, payload in self.rx.feed(data):
                self._take_unsolicited(ftype, payload)
            if time.monotonic() >= end:
                return

    def request(self, ftype, payload=b""):
        """Send a request, wait for its reply (retrying with the same seq): (status, payload)."""
        self.seq = (self.seq % 255) + 1     # 1..255; 0 is the unsolicited frames'
        frame = codec.frame_encode(ftype, self.seq, payload)
        for _ in range(self.retries):
            self.port.write(frame)
            deadline = time.monotonic() + self.reply_timeout
            while time.monotonic() < deadline:
                data = self.port.read(max(1, self.port.in_waiting))
                for rtype, rseq, rpay in self.rx.feed(data):
                    if rtype == (ftype | codec.REPLY) and rseq == self.seq and rpay:
                        return rpay[0], bytes(rpay[1:])
                    self._take_unsolicited(rtype, rpay)
        raise NoAnswer(f"no answer from {self.url} to request 0x{ftype:02x} after {self.retries} tries")

    def _ok(self, ftype, payload=b"", what=""):
        st, p = self.request(ftype, payload)
        if st != codec.ST_OK:
            raise Refused(f"{what or 'request'}: {codec.STATUS_TEXT.get(st, st)}")
        return p

    # ---- table ----------------------------------------------------------------
    def hello(self):
        p = self._ok(codec.HELLO, what="HELLO")
        ver, nvars, vhash, ts_ns, baud, cap_rows, cap_ch, st_vars = struct.unpack_from("<BHIIIHBB", p, 0)
        n = p[19]
        return {"protocol": ver, "n_vars": nvars, "table_hash": vhash, "Ts_s": ts_ns * 1e-9, "baud": baud,
                "capture_rows": cap_rows, "capture_channels": cap_ch, "stream_vars": st_vars,
                "firmware": p[20:20 + n].decode("ascii", "replace")}

    def list_vars(self):
        out, vid = [], 0
        while vid < self.info["n_vars"]:
            p = self._ok(codec.LIST_VARS, struct.pack("<H", vid), "LIST_VARS")
            first, count = struct.unpack_from("<HB", p, 0)
            i = 3
            for k in range(count):
                vtype, acc, scale, lo, hi = struct.unpack_from("<BBfff", p, i)
                i += 14
                n = p[i]
                name = p[i + 1:i + 1 + n].decode("ascii")
                i += 1 + n
                n = p[i]
                unit = p[i + 1:i + 1 + n].decode("ascii")
                i += 1 + n
                out.append(Var(first + k, name, unit, vtype, acc, lo, hi, scale))
            if count == 0:
                raise NoAnswer("LIST_VARS returned no variable")
            vid = first + count
        return out

    def _table(self):
        path = os.path.join(_cache_dir(), f"{self.info['table_hash']:08x}.json")
        if self.use_cache:
            try:
                with open(path) as f:
                    rows = json.load(f)
                if len(rows) == self.info["n_vars"]:
                    return [Var(*r) for r in rows]
            except (OSError, ValueError, TypeError):
                pass
            if os.path.isdir(_cache_dir()) and os.listdir(_cache_dir()):
                self.warn("the drive's variable table changed (reflashed?): listing it again")
        table = self.list_vars()
        if self.use_cache:
            try:
                os.makedirs(_cache_dir(), exist_ok=True)
                with open(path, "w") as f:
                    json.dump([[v.id, v.name, v.unit, v.type, v.access, v.lo, v.hi, v.scale] for v in table], f)
            except OSError:
                pass
        return table

    def var(self, name):
        try:
            return self.by_name[name]
        except KeyError:
            raise UsageError(f"unknown variable '{name}' (drivetool list names them)") from None

    # ---- variables ---------------------------------------------------------------
    def get(self, *names):
        """Values by name (one READ); a dict name -> value."""
        vs = [self.var(n) for n in names]
        out = {}
        for k in range(0, len(vs), 32):
            chunk = vs[k:k + 32]
            p = self._ok(codec.READ, b"".join(struct.pack("<H", v.id) for v in chunk), "READ")
            i = 0
            for v in chunk:
                out[v.name], i = v.decode(p, i)
        return out

    def set(self, name, value):
        """Write through the firmware's cmd_apply(); Refused with its reason."""
        v = self.var(name)
        if v.access == codec.ACC_READ:
            raise Refused(f"{name} is read-only")
        if v.type == codec.T_F32:
            raw = struct.pack("<f", float(value))
        else:
            iv = int(value)
            if iv < 0 or iv > 0xFFFFFFFF:
                raise UsageError(f"{name} takes a whole number >= 0")
            raw = struct.pack("<I", iv)
        st, p = self.request(codec.WRITE, struct.pack("<H", v.id) + raw)
        if st == codec.ST_ACCESS:
            raise Refused(f"{name} is written only while the drive is stopped" if v.access == codec.ACC_WRITE_STOPPED
                          else f"{name} is read-only")
        if st == codec.ST_REFUSED:
            err = struct.unpack_from("<H", p, 0)[0]
            raise Refused(f"{name}={value} refused: {CMD_ERRORS.get(err, err)}")
        if st != codec.ST_OK:
            raise Refused(f"{name}: {codec.STATUS_TEXT.get(st, st)}")

    def action(self, act):
        self._ok(codec.ACTION, bytes([act]), "ACTION")

    def level(self, n):
        """The build level (1 PWM, 2 ADC, 3 encoder check, 4 torque control, 5 the drive) the next
        start runs, set as the command block's `level`; Refused outside 1..5."""
        if not 0 <= n <= 255:
            raise UsageError(f"level {n}: expected 1 to 5")
        st, p = self.request(codec.ACTION, bytes([codec.ACT_LEVEL, n]))
        if st == codec.ST_REFUSED:
            raise Refused(f"level {n} refused: {CMD_ERRORS.get(struct.unpack_from('<H', p, 0)[0], '?')}")
        if st != codec.ST_OK:
            raise Refused(f"ACTION level: {codec.STATUS_TEXT.get(st, st)}")

    def ping(self):
        p = self._ok(codec.PING, what="PING")
        crc, framing, overrun, ticks = struct.unpack_from("<HHHI", p, 0)
        return {"err_crc": crc, "err_framing": framing, "err_overrun": overrun, "ticks": ticks}

    # ---- stream ------------------------------------------------------------------
    def stream_set(self, names, decimate):
        """Start (or with no names stop) the stream; Refused naming the budget when it would not fit."""
        vs = [self.var(n) for n in names]
        st, p = self.request(codec.STREAM_SET, struct.pack("<H", decimate) +
                             b"".join(struct.pack("<H", v.id) for v in vs))
        if st == codec.ST_REFUSED:
            need, budget = struct.unpack_from("<II", p, 0)
            raise Refused(f"stream refused: {len(vs)} variable(s) at {1.0 / (self.info['Ts_s'] * decimate):.0f} Hz "
                          f"need {need} B/s, the link's budget is {budget} B/s "
                          f"(80 % of {self.info['baud']} baud)")
        if st != codec.ST_OK:
            raise Refused(f"STREAM_SET: {codec.STATUS_TEXT.get(st, st)}")
        self.stream_ids = [v.id for v in vs]
        self.stream_rows = []
        return struct.unpack_from("<II", p, 0)

    # ---- capture -----------------------------------------------------------------
    def capture_arm(self, names, trigger=codec.TRIG_FORCED, trig_name=None, level=0.0, hyst=0.0,
                    pre=0, samples=1000, decimate=1):
        vs = [self.var(n) for n in names]
        if not 1 <= len(vs) <= self.info["capture_channels"]:
            raise UsageError(f"capture takes 1 to {self.info['capture_channels']} variables")
        if not 1 <= samples <= self.info["capture_rows"] or not 0 <= pre < samples or decimate < 1:
            raise UsageError(f"need 0 <= --pre < --samples <= {self.info['capture_rows']} and --decimate >= 1")
        tid = self.var(trig_name).id if trig_name else 0
        p = struct.pack("<HHHBHffB", decimate, pre, samples, trigger, tid, level, hyst, len(vs))
        p += b"".join(struct.pack("<H", v.id) for v in vs)
        st, r = self.request(codec.CAPTURE_ARM, p)
        if st == codec.ST_BAD_REQUEST and len(r) >= 2:   # too deep for these channels' slots
            raise UsageError(f"--samples {samples}: at most {struct.unpack_from('<H', r, 0)[0]} rows with these "
                             "channels (a float32 channel takes two of the capture's int16 slots a row)")
        if st != codec.ST_OK:
            raise Refused(f"CAPTURE_ARM: {codec.STATUS_TEXT.get(st, st)}")

    def capture_status(self):
        p = self._ok(codec.CAPTURE_STATUS, what="CAPTURE_STATUS")
        state, samples, pre, dec, trig_idx, first_idx, nch = struct.unpack_from("<BHHHIIB", p, 0)
        ch = [struct.unpack_from("<Hf", p, 16 + 6 * k) for k in range(nch)]
        at = 16 + 6 * nch                           # then each channel's format (a firmware before it: int16)
        fmt = list(p[at:at + nch]) if len(p) >= at + nch else [codec.CAP_I16] * nch
        return {"state": state, "samples": samples, "pre": pre, "decimate": dec, "trigger_index": trig_idx,
                "first_index": first_idx, "channels": ch, "formats": fmt}

    def capture_read(self, status, depth=3):
        """Every row of a finished capture: (t_s list, rows of values). Pages are asked
        `depth` at a time (CAPTURE_READ reads, it changes nothing: a page whose reply
        was lost is simply asked again), so the host's turnaround does not idle the line."""
        n = status["samples"]
        row_fmt = "<" + "".join("f" if f == codec.CAP_F32 else "h" for f in status.get("formats", []))
        row_fmt = row_fmt if len(row_fmt) > 1 else "<" + "h" * len(status["channels"])
        row_bytes = struct.calcsize(row_fmt)
        page = (codec.PAYLOAD_MAX - 5) // row_bytes
        pages = {}                                  # first row -> counts
        todo = list(range(0, n, page))
        stalls = 0                                  # rounds in a row that got no page
        while todo and stalls < self.retries:
            sent = {}
            for first in todo[:depth]:
                self.seq = (self.seq % 255) + 1
                sent[self.seq] = first
                self.port.write(codec.frame_encode(codec.CAPTURE_READ, self.seq,
                                                   struct.pack("<HH", first, min(page, n - first))))
            deadline = time.monotonic() + self.reply_timeout * len(sent)
            while sent and time.monotonic() < deadline:
                data = self.port.read(max(1, self.port.in_waiting))
                for rtype, rseq, rpay in self.rx.feed(data):
                    if rtype != (codec.CAPTURE_READ | codec.REPLY) or rseq not in sent:
                        self._take_unsolicited(rtype, rpay)
                        continue
                    first = sent.pop(rseq)
                    if not rpay or rpay[0] != codec.ST_OK:
                        raise Refused(f"CAPTURE_READ: {codec.STATUS_TEXT.get(rpay[0] if rpay else -1, '?')}")
                    f, rows = struct.unpack_from("<HH", rpay, 1)
                    if f != first or rows != min(page, n - first):
                        raise NoAnswer("CAPTURE_READ answered another page")
                    pages[first] = [struct.unpack_from(row_fmt, rpay, 5 + row_bytes * r) for r in range(rows)]
            left = [first for first in range(0, n, page) if first not in pages]
            stalls = stalls + 1 if len(left) == len(todo) else 0
            todo = left
        if todo:
            raise NoAnswer(f"no answer from {self.url} to CAPTURE_READ after {self.retries} tries")
        counts = [row for first in sorted(pages) for row in pages[first]]
        ts = self.info["Ts_s"]
        t = [(status["first_index"] + r * status["decimate"]) * ts for r in range(n)]
        rows = [[c * lsb for c, (_vid, lsb) in zip(row, status["channels"])] for row in counts]
        return t, rows

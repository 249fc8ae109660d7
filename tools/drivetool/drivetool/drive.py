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
import math
import os
import socket
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
    9: "a fault is latched: reset it first",
    10: "the drive is not stopped: stop it first",
    11: "not finite or outside the variable's limits",
}
CMD_ERR_FAULTED, CMD_ERR_NOT_STOPPED, CMD_ERR_RANGE = 9, 10, 11
# the firmware's enumerations (firmware/protect/app_step.h, control/ctrl/ctrl.h, control/est/est.h,
# firmware/commission/commission.h)
STATES = ["INIT", "IDLE", "CALIBRATE", "ALIGN", "IDENTIFY_R", "RUN", "FAULT", "PWM_CHECK", "ADC_CHECK",
          "ENC_CHECK", "COMMISSION"]
FAULTS = ["NONE", "HW_TRIP", "OVERCURRENT", "NONFINITE_OUTPUT", "NONFINITE_SAMPLE", "OVERVOLTAGE",
          "UNDERVOLTAGE", "OVERSPEED", "ENCODER", "OVERRUN", "CURRENT_OFFSET", "CONFIG", "RSID_TOO_FEW",
          "RSID_NOT_STEADY", "RSID_DEGENERATE", "RSID_NON_FINITE", "RSID_OUT_OF_BAND", "OPEN_PHASE",
          "CURRENT_SENSOR", "ENCODER_LOST", "WATCHDOG_RESET", "FLASH_CRC", "ENCODER_DIRECTION", "POLE_PAIRS",
          "PHASE_ORDER", "RSID_D_AXIS", "COMM_TIMEOUT", "COMM_NO_ROTATION", "COMM_IMPLAUSIBLE",
          "BUS_CHARGED", "RSID_INVERTER"]
MODES = ["open_loop", "torque", "speed"]             # ctrl_mode_t (drive_sil's [controller] mode names)
METHODS = ["conventional", "proposed"]              # ctrl_method_t (drive_sil's [controller] method names)
EST_PHASES = ["off", "step1", "step2"]
COMM_RESULTS = ["none", "running", "done", "refused"]
COMM_STAGES = ["NONE", "R", "L", "ENCODER", "SPIN", "DONE", "WIRING", "INVERTER"]
LEVELS = ["-", "pwm", "adc", "encoder_check", "torque", "drive"]
CMD_ERROR_NAMES = ["OK", "METHOD", "METHOD_CFG", "MODE", "SPEED", "TORQUE", "VOLTAGE", "METHOD_NO_STEP1", "LEVEL",
                   "FAULTED", "NOT_STOPPED", "RANGE"]
# nv_status: the parameter store's state (link_nv_status_t, firmware/link/link_nv.h)
NV_STATUSES = ["NONE", "EMPTY", "VALID", "INVALID", "SAVING", "SAVED", "SAVE_FAILED"]
NV_NONE, NV_SAVING, NV_SAVED, NV_SAVE_FAILED = 0, 4, 5, 6
# the bits of `flags` (CTRL_FLAG_*, then the app's warnings APP_WARN_*) and of `est_hold` / `hold_reason`
FLAG_BITS = {0x0001: "VOLTAGE_LIMIT", 0x0002: "FLUX_UNREACHABLE", 0x0004: "NONFINITE", 0x0100: "INV_UNIDENTIFIED",
             0x0200: "R_HELD", 0x0400: "PSI_HELD", 0x0800: "ANGLE_SUSPECT", 0x1000: "STEP1_REFUSED",
             0x2000: "HOST_TIMEOUT", 0x4000: "OSCILLATION"}
HOLD_BITS = {0x0001: "ACCEL", 0x0002: "CURRENT", 0x0004: "TORQUE", 0x0008: "VOLTAGE", 0x0010: "SETTLE",
             0x0020: "SPEED_FLOOR", 0x0040: "NO_STEP2", 0x0080: "ANGLE", 0x0100: "STEP1_REFUSED",
             0x0200: "INVERTER_UNKNOWN", 0x0400: "OSCILLATION"}
WARNING_BITS = 0x7000           # the app's warnings among the flags
# variable -> the names of its values (shown by name, numbers with --json; accepted by name in set)
ENUMS = {"state": STATES, "fault": FAULTS, "fault_present": FAULTS, "mode": MODES, "method": METHODS,
         "method_ran": METHODS, "est": EST_PHASES, "comm_result": COMM_RESULTS, "comm_stage": COMM_STAGES,
         "level": LEVELS, "level_next": LEVELS, "cmd_error": CMD_ERROR_NAMES, "nv_status": NV_STATUSES}
BITS = {"flags": FLAG_BITS, "est_hold": HOLD_BITS, "hold_reason": HOLD_BITS}
ACCESS = {codec.ACC_READ: "r", codec.ACC_WRITE: "rw", codec.ACC_WRITE_STOPPED: "rw-stopped"}
TYPES = {codec.T_U16: "u16", codec.T_U32: "u32", codec.T_F32: "f32"}
LIST_PARAM = 0x02               # LIST_VARS' byte after the descriptors: a parameter of the drive (bit 0: format)


def enum_name(var, value):
    """The name of an enumerated variable's value (its number when it has none)."""
    names = ENUMS.get(var)
    return names[value] if names is not None and 0 <= value < len(names) else str(value)


def bits_names(var, value):
    """'0x2020 SPEED_FLOOR HOST_TIMEOUT': a bit set's value and the names of its bits ('0x0000' for none)."""
    names = [n for b, n in sorted(BITS[var].items()) if value & b]
    rest = value & ~sum(b for b in BITS[var] if value & b)
    return " ".join([f"0x{value:04x}"] + names + ([f"0x{rest:04x}?"] if rest else []))


def show(var, value):
    """A value as drivetool prints it without --json: enumerations and bit sets by name."""
    if var in ENUMS:
        return enum_name(var, value)
    if var in BITS:
        return bits_names(var, value)
    return f"{value:.6g}" if isinstance(value, float) else str(value)


class LinkError(Exception):
    """Base of the drive's errors; `code` is drivetool's exit status."""
    code = 1


class Refused(LinkError):
    """The firmware refused the request (the reason in the message; its cmd_error in err, when it said)."""
    code = 1

    def __init__(self, message, err=None):
        super().__init__(message)
        self.err = err


class UsageError(LinkError):
    """Bad usage or an unknown variable name."""
    code = 2


class NoAnswer(LinkError):
    """No port, or no reply after the retries."""
    code = 3


class Held(NoAnswer):
    """The port serves another client (drive_sil --link: one at a time)."""


RETRIES = 6                 # tries of a request before NoAnswer (and an upload's reply times of silence)
# CAPTURE_READ: its request's bytes on the wire (type, seq, first, rows, CRC, COBS, delimiter), its
# reply's header (status, first, rows); a run of this many replies grows the page by 1/PAGE_GROW_DIV
# (at least a row): a loss halves it (at 2 % byte loss it settles near the goodput's best, 4-8 rows
# of 4 bytes, where a page is lost about every second try)
CAP_READ_REQUEST_BYTES = 10
CAP_READ_HEADER = 5
PAGE_GROW_AFTER = 1
PAGE_GROW_DIV = 4
REPLY_MARGIN_S = 0.15       # a reply's time beyond its bytes: the drive's background loop, the host's scheduling
# ... for a capture's page: shorter (a page asked again too early costs a few bytes, and its late
# reply's rows are kept all the same)
PAGE_MARGIN_S = 0.05
BITS_PER_BYTE = 10          # 8N1
HELD_RETRY_S = 0.1          # a held port is tried again this often until the open's timeout
# save: the board erases and programs its flash sector with the control ISR and the link held off (an
# erase takes about a second, SPRS439's flash timing; the API's worst case is longer): the save's
# requests keep being retried, unanswered, for this long, polling nv_status this often
SAVE_WAIT_S = 30.0
SAVE_POLL_S = 0.1
# while only listening (a stream), a PING this often: the drive's host timeout and drive_sil's idle
# timeout see a host that is there (a fifth of the shortest timeout, 1 s)
KEEPALIVE_S = 0.2


class Var:
    def __init__(self, vid, name, unit, vtype, access, lo, hi, scale, extra=0):
        self.id, self.name, self.unit, self.type, self.access = vid, name, unit, vtype, access
        self.lo, self.hi, self.scale = lo, hi, scale
        self.fmt = extra & 1                    # its capture format: codec.CAP_I16 or CAP_F32
        self.param = bool(extra & LIST_PARAM)   # a parameter of the drive (link_params.h)
        self.extra = extra

    def to_dict(self):
        return {"id": self.id, "name": self.name, "unit": self.unit, "type": TYPES[self.type],
                "access": ACCESS.get(self.access, str(self.access)), "min": self.lo, "max": self.hi,
                "scale": self.scale, "capture": "float32" if self.fmt == codec.CAP_F32 else "int16",
                "parameter": self.param}

    def parse(self, text):
        """A value given as text (a name for an enumeration): a number of this variable's type;
        UsageError naming the problem (a fraction for an integer, an unknown name)."""
        names = ENUMS.get(self.name)
        if names is not None and text in names:
            return names.index(text)
        try:
            v = float(text)
        except ValueError:
            hint = f" (or one of: {', '.join(names)})" if names else ""
            raise UsageError(f"{self.name}: {text!r} is not a number{hint}") from None
        return self.check(v)

    def check(self, v):
        """v as this variable's type: a whole number for an integer one (a fraction refused)."""
        if self.type == codec.T_F32:
            return float(v)
        if not float(v).is_integer():
            raise UsageError(f"{self.name} takes a whole number, not {v!r}")
        if not 0 <= v <= (0xFFFF if self.type == codec.T_U16 else 0xFFFFFFFF):
            raise UsageError(f"{self.name} takes a whole number from 0 to "
                             f"{0xFFFF if self.type == codec.T_U16 else 0xFFFFFFFF}, not {v!r}")
        return int(v)

    def decode(self, b, i):
        """The value at b[i:], and the index after it."""
        if self.type == codec.T_U16:
            return struct.unpack_from("<H", b, i)[0], i + 2
        if self.type == codec.T_U32:
            return struct.unpack_from("<I", b, i)[0], i + 4
        return struct.unpack_from("<f", b, i)[0], i + 4


class _CapturePage:
    """capture_read's page [rows]: halved by a lost request (at least a row), grown by
    1/PAGE_GROW_DIV (at least a row, at most the reply's room) after PAGE_GROW_AFTER replies."""

    def __init__(self, rows_max):
        self.rows = rows_max
        self.rows_max = rows_max
        self.good_run = 0

    def lost(self):
        self.rows = max(1, self.rows // 2)
        self.good_run = 0

    def answered(self):
        self.good_run += 1
        if self.good_run >= PAGE_GROW_AFTER and self.rows < self.rows_max:
            self.rows = min(self.rows_max, self.rows + max(1, self.rows // PAGE_GROW_DIV))
            self.good_run = 0


def _capture_row_format(status):
    """A capture row's struct format from capture_status: a float32 or int16 per channel (int16 all
    when the firmware names no formats)."""
    row_fmt = "<" + "".join("f" if f == codec.CAP_F32 else "h" for f in status.get("formats", []))
    return row_fmt if len(row_fmt) > 1 else "<" + "h" * len(status["channels"])


def _capture_rows_into(got, rpay, row_fmt, row_bytes):
    """A CAPTURE_READ reply's rows into got, by the rows the reply names whatever asked; how many of
    them were missing. Refused: the drive's status; NoAnswer: rows outside the capture."""
    if not rpay or rpay[0] != codec.ST_OK:
        raise Refused(f"CAPTURE_READ: {codec.STATUS_TEXT.get(rpay[0] if rpay else -1, '?')}")
    f, rows = struct.unpack_from("<HH", rpay, 1)
    if f + rows > len(got) or len(rpay) < CAP_READ_HEADER + rows * row_bytes:
        raise NoAnswer("CAPTURE_READ answered rows outside the capture")
    filled = 0
    for r in range(rows):
        filled += got[f + r] is None
        got[f + r] = struct.unpack_from(row_fmt, rpay, CAP_READ_HEADER + row_bytes * r)
    return filled


def _capture_answered(inflight, rseq, page):
    """A reply to request rseq: it leaves inflight, and, the drive answering in order, every request
    sent before it is lost (page.lost()); a reply to none in flight changes nothing."""
    if rseq in inflight:
        for q in list(inflight):
            if q == rseq:
                break
            del inflight[q]
            page.lost()
        del inflight[rseq]


CACHE_ROW = 9                   # a cached descriptor's fields (an older cache's 8: listed again)


def _cache_dir():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "drivetool")


class Drive:
    def __init__(self, url, timeout=2.0, baud=115200, retries=RETRIES, cache=True, warn=None):
        self.url, self.baud, self.retries, self.use_cache = url, baud, retries, cache
        self.warn = warn or (lambda msg: None)
        self.rx = codec.Receiver()
        self.seq = 0
        self.stream_rows = []       # (period index, [values]) of unsolicited stream frames
        self.stream_ids = []
        self.events = []            # (state, fault, period index)
        self.last_tx_s = 0.0        # when the last request went out (time.monotonic)
        # a reply at the line's rate, with room for the drive's background loop
        self.reply_timeout = REPLY_MARGIN_S + 2 * (codec.PAYLOAD_MAX + codec.FRAME_OVERHEAD) * BITS_PER_BYTE / baud
        deadline = time.monotonic() + timeout
        while True:                 # a port held by another client is tried again until the timeout
            self.port = self._open(url, deadline, baud)
            try:
                self.info = self.hello()
                break
            except Held:
                self.port.close()
                if time.monotonic() >= deadline:
                    raise
                time.sleep(HELD_RETRY_S)
        self.vars = self._table()
        self.by_name = {v.name: v for v in self.vars}

    # ---- port ---------------------------------------------------------------
    @staticmethod
    def _open(url, deadline, baud):
        try:
            import serial  # pyserial
        except ImportError as e:  # pragma: no cover - the venv has it
            raise NoAnswer("pyserial is not installed (make drivetool)") from e
        while True:
            try:
                port = serial.serial_for_url(url, baudrate=baud, timeout=0.02)
                sock = getattr(port, "_socket", None)      # socket://: pyserial's own socket
                if sock is not None:
                    # each request at once: Nagle would hold a pipelined one for the drive's ACK
                    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                return port
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

    def _read(self):
        """What the port has (at most its read timeout's wait); NoAnswer when the drive closed it."""
        try:
            return self.port.read(max(1, self.port.in_waiting))
        except OSError as e:        # pyserial's SerialException: the connection is gone
            raise NoAnswer(f"{self.url}: the drive closed the connection ({e})") from None

    def _write(self, frame):
        try:
            self.port.write(frame)
        except OSError as e:        # pyserial's SerialException: the connection is gone
            raise NoAnswer(f"{self.url}: the drive closed the connection ({e})") from None
        self.last_tx_s = time.monotonic()

    def _take_unsolicited(self, ftype, payload):
        if ftype == codec.NOTICE and payload:
            text = payload[1:].decode("ascii", "replace")
            if payload[0] == codec.NOTICE_HELD:
                raise Held(f"{self.url}: {text} (drive_sil --link serves one client at a time)")
            raise NoAnswer(f"{self.url}: {text}")
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
        """Read what has come (for up to `wait` s), keeping stream rows and events; a PING every
        KEEPALIVE_S meanwhile (a host that only listens is still there)."""
        end = time.monotonic() + wait
        while True:
            if time.monotonic() - self.last_tx_s >= KEEPALIVE_S:
                self.ping()
            data = self._read()
            for ftype, _seq, payload in self.rx.feed(data):
                self._take_unsolicited(ftype, payload)
            if time.monotonic() >= end:
                return

    def request(self, ftype, payload=b""):
        """Send a request, wait for its reply (retrying with the same seq): (status, payload)."""
        self.seq = (self.seq % 255) + 1     # 1..255; 0 is the unsolicited frames'
        frame = codec.frame_encode(ftype, self.seq, payload)
        for _ in range(self.retries):
            self._write(frame)
            deadline = time.monotonic() + self.reply_timeout
            while time.monotonic() < deadline:
                data = self._read()
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
            listed = []
            for k in range(count):
                vtype, acc, scale, lo, hi = struct.unpack_from("<BBfff", p, i)
                i += 14
                n = p[i]
                name = p[i + 1:i + 1 + n].decode("ascii")
                i += 1 + n
                n = p[i]
                unit = p[i + 1:i + 1 + n].decode("ascii")
                i += 1 + n
                listed.append([first + k, name, unit, vtype, acc, lo, hi, scale])
            extra = list(p[i:i + count]) if len(p) >= i + count else [0] * count   # an older drive: none
            out += [Var(*v, x) for v, x in zip(listed, extra)]
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
                if len(rows) == self.info["n_vars"] and all(len(r) == CACHE_ROW for r in rows):
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
                    json.dump([[v.id, v.name, v.unit, v.type, v.access, v.lo, v.hi, v.scale, v.extra] for v in table],
                              f)
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
        """Write through the firmware's checks (cmd_apply(), a setting's or a parameter's limits);
        Refused with its reason. An integer variable takes a whole number (UsageError else)."""
        v = self.var(name)
        if v.access == codec.ACC_READ:
            raise Refused(f"{name} is read-only")
        value = v.check(value)
        raw = struct.pack("<f", value) if v.type == codec.T_F32 else struct.pack("<I", value)
        st, p = self.request(codec.WRITE, struct.pack("<H", v.id) + raw)
        if st == codec.ST_ACCESS:
            raise Refused(f"{name} is written only while the drive is stopped" if v.access == codec.ACC_WRITE_STOPPED
                          else f"{name} is read-only")
        if st == codec.ST_REFUSED:
            err = struct.unpack_from("<H", p, 0)[0]
            why = CMD_ERRORS.get(err, err)
            if err == CMD_ERR_RANGE:
                why = f"outside {name}'s limits {v.lo:.6g} .. {v.hi:.6g} {v.unit}".rstrip()
            raise Refused(f"{name}={value} refused: {why}", err)
        if st != codec.ST_OK:
            raise Refused(f"{name}: {codec.STATUS_TEXT.get(st, st)}")

    def action(self, act):
        """An action; Refused (its cmd_error in .err) when the drive's state made it do nothing."""
        st, p = self.request(codec.ACTION, bytes([act]))
        if st == codec.ST_REFUSED and len(p) >= 2:
            err = struct.unpack_from("<H", p, 0)[0]
            raise Refused(f"ACTION {act}: {CMD_ERRORS.get(err, err)}", err)
        if st != codec.ST_OK:
            raise Refused(f"ACTION: {codec.STATUS_TEXT.get(st, st)}")

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

    def save(self, wait=SAVE_WAIT_S):
        """The drive's parameters into its store (the drive stopped): ACTION save, then nv_status until
        SAVED (returned) or SAVE_FAILED (Refused); a drive silent while it writes its flash is asked
        again for up to `wait` s. Refused with CMD_ERR_NOT_STOPPED (in .err) while the drive is not
        stopped, and without a store (an image or drive_sil run without one: nv_status NONE)."""
        if "nv_status" not in self.by_name or self.get("nv_status")["nv_status"] == NV_NONE:
            raise Refused("save: this drive has no parameter store (drive_sil: --nv FILE)")
        deadline = time.monotonic() + wait
        retries = self.retries
        self.retries = max(retries, math.ceil(wait / self.reply_timeout))   # the repeat answered after the write
        try:
            self.action(codec.ACT_SAVE)
        finally:
            self.retries = retries
        while True:
            try:
                st = self.get("nv_status")["nv_status"]
            except NoAnswer:
                st = NV_SAVING      # writing its flash: no answer meanwhile
            if st == NV_SAVED:
                return st
            if st == NV_SAVE_FAILED:
                raise Refused("save failed: the flash refused the block or it did not read back, or the drive was "
                              "started before it was written (nv_status SAVE_FAILED)")
            if time.monotonic() > deadline:
                raise NoAnswer(f"save: nv_status still {enum_name('nv_status', st)} after {wait:g} s")
            time.sleep(SAVE_POLL_S)

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
        """Every row of a finished capture: (t_s list, rows of values). A window of `depth`
        CAPTURE_READ requests in flight, so the host's turnaround does not idle the line; each
        reply names the rows it holds, so every row received is kept whatever the request was, and
        only the rows still missing are asked again. A page is lost when a later request's reply
        comes first (the drive answers in order) or its reply does not come within its time (its
        bytes at the line's rate, a margin): its rows are asked again and the page halves (at
        least one row); each reply grows it again by a quarter. The upload gives
        up (NoAnswer) after `retries` request reply times (reply_timeout) with no reply at all."""
        n = status["samples"]
        row_fmt = _capture_row_format(status)
        row_bytes = struct.calcsize(row_fmt)
        page = _CapturePage(max(1, (codec.PAYLOAD_MAX - CAP_READ_HEADER) // row_bytes))
        got = [None] * n                            # row -> counts
        missing = n
        inflight = {}                               # seq -> (first, rows, deadline), in the order sent
        silent_s = self.retries * self.reply_timeout
        last_reply = time.monotonic()
        while missing:
            now = time.monotonic()
            for seq in [q for q, (_f, _r, dl) in inflight.items() if dl < now]:
                del inflight[seq]                   # lost: its rows are asked again, a smaller page
                page.lost()
            if now - last_reply > silent_s:
                raise NoAnswer(f"no answer from {self.url} to CAPTURE_READ for {silent_s:.2g} s "
                               f"({missing} of {n} rows missing)")
            self._capture_requests(got, inflight, page.rows, depth, row_bytes)
            for rtype, rseq, rpay in self.rx.feed(self._read()):
                if rtype != (codec.CAPTURE_READ | codec.REPLY):
                    self._take_unsolicited(rtype, rpay)
                    continue
                missing -= _capture_rows_into(got, rpay, row_fmt, row_bytes)
                _capture_answered(inflight, rseq, page)
                last_reply = time.monotonic()
                page.answered()
        ts = self.info["Ts_s"]
        t = [(status["first_index"] + r * status["decimate"]) * ts for r in range(n)]
        rows = [[c * lsb for c, (_vid, lsb) in zip(row, status["channels"])] for row in got]
        return t, rows

    def _capture_requests(self, got, inflight, page_rows, depth, row_bytes):
        """capture_read's requests: CAPTURE_READ of the first missing rows no request in flight
        covers (at most page_rows), sent until `depth` are in flight, each with its deadline."""
        while len(inflight) < depth:
            first, rows = self._next_missing(got, inflight, page_rows)
            if first is None:
                break
            self.seq = (self.seq % 255) + 1
            self._write(codec.frame_encode(codec.CAPTURE_READ, self.seq, struct.pack("<HH", first, rows)))
            inflight[self.seq] = (first, rows, time.monotonic() + self._page_time(rows * row_bytes))

    def _page_time(self, reply_payload):
        """How long a CAPTURE_READ's reply of this payload may take: the request and the reply at
        the line's rate, and the drive's background and the host's scheduling (PAGE_MARGIN_S)."""
        wire = CAP_READ_REQUEST_BYTES + reply_payload + CAP_READ_HEADER + codec.FRAME_OVERHEAD
        return PAGE_MARGIN_S + wire * BITS_PER_BYTE / self.baud

    @staticmethod
    def _next_missing(got, inflight, page):
        """The first run of missing rows no request in flight covers, at most `page` long:
        (first, rows), or (None, 0)."""
        asked = set()
        for first, rows, _dl in inflight.values():
            asked.update(range(first, first + rows))
        first = next((r for r, row in enumerate(got) if row is None and r not in asked), None)
        if first is None:
            return None, 0
        rows = 1
        while rows < page and first + rows < len(got) and got[first + rows] is None and first + rows not in asked:
            rows += 1
        return first, rows

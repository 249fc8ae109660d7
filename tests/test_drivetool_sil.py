"""drivetool against drive_sil --link (tools/sil/link_sil.h): a round trip at
--realtime 1 (status; a capture of iq_meas_A and speed_est_rpm triggered by
speed_est_rpm>250 with 100 pre-trigger rows, compared with drive_sil's own
CSV at the same t_s), the exit codes, a stream refused above the line's
budget, and a lossy link (drops, flips, duplicates, garbage at 10 % of the
bytes each way) where every write completes or fails cleanly and is applied
once; `drivetool commission` on the paper motor (Table I) with a free
shaft: the values within the commissioning's tolerances (R, L, psi_f 3 %,
J 10 %, the pole pairs exact) written as a [controller] section, and a
reversed encoder refused naming ENCODER_DIRECTION (exit 1). Issue 29: the
socket's clients (a second one told the link is held, a silent one dropped,
killed, garbage, half-closed), the host timeout (ramp, stop, HOST_TIMEOUT
named; off by default), actions refused naming the fault or the state, the
parameters (stopped only, the scenario keys' ranges, backup as an INI
drive_sil accepts, restore exact and all or nothing), drivetool's daily use
(help with defaults, names unless --json, DRIVETOOL_PORT, fractions refused,
Ctrl-C exit 130, list's ranges and formats) and a capture armed and fetched
through a line dropping 2 % of the bytes each way. Simulated time is read
from drive_sil's CSV where it matters, never guessed from the wall clock;
ports come from the OS. Needs the built drive_sil and drivetool (DRIVE_SIL,
DRIVETOOL: make test-tools sets them); skipped without them."""
import csv
import json
import os
import random
import re
import socket
import subprocess
import sys
import tempfile
import threading
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tools", "drivetool"))

DRIVE_SIL = os.environ.get("DRIVE_SIL", os.path.join(ROOT, "build", "host", "drive_sil"))
DRIVETOOL = os.environ.get("DRIVETOOL", os.path.join(ROOT, "build", "venv", "bin", "drivetool"))
try:
    import serial  # noqa: F401  (pyserial: the Drive API's port)
    HAVE_SERIAL = True
except ImportError:
    HAVE_SERIAL = False

# Speed ramps 0 <-> 500 r/min every 2 s from t = 2 s to 16 s (a profile holds 32
# points at most): whenever the capture is
# armed, an upward crossing of 250 r/min follows within 2 s.
RAMPS = "".join(f"\n    {t}:0, {t + 0.2:.1f}:500~, {t + 1}:500, {t + 1.2:.1f}:0~" for t in range(2, 16, 2))
SCENARIO = f"""[plant]
model = averaged
[controller]
method = conventional
mode = speed
[reference]
speed_rpm = 0:0{RAMPS}
[load]
torque_Nm = 0:1
[run]
duration_s = 0
log_every = 1
"""
TRIGGER_RPM = 250.0
PRE, SAMPLES = 100, 1000
TS = 1e-4                     # the board's period (drive_sil's default), checked against HELLO


def start_sil(tmp, *extra, scenario=SCENARIO, stdout_path=None):
    ini = os.path.join(tmp, "link.ini")
    with open(ini, "w") as f:
        f.write(scenario)
    err_path = os.path.join(tmp, "drive_sil.err")
    with open(err_path, "w") as err, open(stdout_path or os.devnull, "w") as out:
        p = subprocess.Popen([DRIVE_SIL, "--scenario", ini, "--link", "tcp:0", *extra],
                             stdout=out, stderr=err)
    deadline = time.monotonic() + 30
    line = ""
    while not line.endswith("\n") and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
        with open(err_path) as f:
            line = f.readline()
    if not line.startswith("listening on 127.0.0.1:"):
        p.kill()
        p.wait()
        raise AssertionError(f"drive_sil did not listen: {line!r}")
    return p, int(line.rsplit(":", 1)[1])


def tool(port, *args, timeout=60, cache=None):
    r = subprocess.run([DRIVETOOL, "--port", f"socket://127.0.0.1:{port}", *args], capture_output=True,
                       text=True, timeout=timeout, env=dict(os.environ, XDG_CACHE_HOME=cache or tempfile.gettempdir()))
    return r.returncode, r.stdout, r.stderr


def finish(p, port):
    rc, _out, err = tool(port, "quit")
    try:
        p.wait(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        raise
    return rc, err


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class RoundTrip(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()
        cls.csv_path = os.path.join(cls.tmp, "run.csv")
        cls.cap_path = os.path.join(cls.tmp, "cap.csv")
        cls.p, cls.port = start_sil(cls.tmp, "--realtime", "1", "--out", cls.csv_path)
        cls.status = tool(cls.port, "--json", "status")
        # the table cache: a cache holding another table's listing (a reflashed board) warns
        cls.cache = tempfile.mkdtemp()
        os.makedirs(os.path.join(cls.cache, "drivetool"))
        with open(os.path.join(cls.cache, "drivetool", "00000000.json"), "w") as f:
            f.write("[]")
        cls.cache_first = tool(cls.port, "status", cache=cls.cache)
        cls.cache_again = tool(cls.port, "status", cache=cls.cache)
        cls.capture = tool(cls.port, "--json", "capture", "iq_meas_A", "speed_est_rpm",
                           "--trigger", f"speed_est_rpm>{TRIGGER_RPM:g}", "--pre", str(PRE),
                           "--samples", str(SAMPLES), "--csv", cls.cap_path)
        cls.cap_f32_path = os.path.join(cls.tmp, "cap_f32.csv")
        cls.capture_f32 = tool(cls.port, "--json", "capture", "L_est_H", "iq_meas_A", "psif_est_Wb",
                               "--trigger", "forced", "--samples", "300", "--csv", cls.cap_f32_path)
        cls.capture_too_deep = tool(cls.port, "capture", "L_est_H", "iq_meas_A", "psif_est_Wb",
                                    "--trigger", "forced", "--samples", "1000")
        cls.stream_refused = tool(cls.port, "stream", "iq_meas_A", "id_meas_A", "speed_est_rpm", "te_est_Nm",
                                  "--rate", "10000", "--duration", "0.1")
        cls.stream_ok = tool(cls.port, "--json", "stream", "speed_est_rpm", "--rate", "100", "--duration", "0.5")
        cls.unknown = tool(cls.port, "get", "no_such_variable")
        cls.refused = tool(cls.port, "set", "speed_ref_rpm=1e6")
        cls.readonly = tool(cls.port, "set", "speed_est_rpm=1")
        cls.backup_path = os.path.join(cls.tmp, "backup.json")     # FILE.json: drivetool's earlier backup
        cls.backup = tool(cls.port, "backup", cls.backup_path)
        cls.set_te = tool(cls.port, "set", "te_cmd_Nm=1.5")
        cls.restore = tool(cls.port, "--json", "restore", cls.backup_path)
        cls.after_restore = tool(cls.port, "--json", "get", "te_cmd_Nm")
        cls.quit_rc, _ = finish(cls.p, cls.port)

    def test_status_has_state_fault_speed(self):
        rc, out, err = self.status
        self.assertEqual(rc, 0, err)
        s = json.loads(out)
        self.assertEqual(s["state_name"], "RUN")
        self.assertEqual(s["fault"], 0)
        self.assertIn("speed_est_rpm", s)

    def test_the_table_is_cached_by_its_hash(self):
        rc, _out, err = self.cache_first
        self.assertEqual(rc, 0, err)
        self.assertIn("variable table changed", err)
        rc, _out, err = self.cache_again                  # now cached under the drive's hash: no warning
        self.assertEqual(rc, 0, err)
        self.assertEqual(err, "")
        self.assertEqual(len(os.listdir(os.path.join(self.cache, "drivetool"))), 2)

    def test_capture_equals_the_csv_at_the_same_t(self):
        rc, out, err = self.capture
        self.assertEqual(rc, 0, err)
        info = json.loads(out)
        lsb_iq, lsb_n = info["lsb"]["iq_meas_A"], info["lsb"]["speed_est_rpm"]
        self.assertLessEqual(lsb_iq, 0.02)
        self.assertLessEqual(lsb_n, 0.5)
        with open(self.cap_path) as f:
            cap = list(csv.DictReader(f))
        self.assertEqual(len(cap), SAMPLES)
        with open(self.csv_path) as f:
            run = {round(float(r["t_s"]) / TS): r for r in csv.DictReader(f)}
        idx = [round(float(r["t_s"]) / TS) for r in cap]
        self.assertEqual(idx, list(range(idx[0], idx[0] + SAMPLES)))      # consecutive periods
        for r, k in zip(cap, idx):
            row = run[k]
            self.assertAlmostEqual(float(r["t_s"]), float(row["t_s"]), delta=TS / 100)
            self.assertLessEqual(abs(float(r["iq_meas_A"]) - float(row["iq_meas_A"])), lsb_iq)
            self.assertLessEqual(abs(float(r["speed_est_rpm"]) - float(row["speed_est_rpm"])), lsb_n)
        # the trigger row is row PRE: the CSV's first sample above 250 r/min after one at or below
        k_trig = idx[PRE]
        self.assertAlmostEqual(info["trigger_t_s"], k_trig * TS, delta=TS / 100)
        self.assertGreater(float(run[k_trig]["speed_est_rpm"]), TRIGGER_RPM)
        self.assertLessEqual(float(run[k_trig - 1]["speed_est_rpm"]), TRIGGER_RPM)

    def test_float32_capture_equals_the_csv_exactly(self):
        # L_est_H and psif_est_Wb ask for float32 (link_vars.c): each captured value is the
        # CSV's own (both print the float with 9 digits); as int16 counts L^ would be off by
        # up to half an LSB (2 L / 65534 / 2, about 3e-8 H), so the equality tells the formats apart
        rc, out, err = self.capture_f32
        self.assertEqual(rc, 0, err)
        info = json.loads(out)
        self.assertEqual(info["format"], {"L_est_H": "float32", "iq_meas_A": "int16", "psif_est_Wb": "float32"})
        self.assertIsNone(info["lsb"]["L_est_H"])
        with open(self.cap_f32_path) as f:
            cap = list(csv.DictReader(f))
        self.assertEqual(len(cap), 300)
        with open(self.csv_path) as f:
            run = {round(float(r["t_s"]) / TS): r for r in csv.DictReader(f)}
        for r in cap:
            row = run[round(float(r["t_s"]) / TS)]
            self.assertEqual(float(r["L_est_H"]), float(row["L_est_H"]))
            self.assertEqual(float(r["psif_est_Wb"]), float(row["psif_est_Wb"]))
            self.assertLessEqual(abs(float(r["iq_meas_A"]) - float(row["iq_meas_A"])), info["lsb"]["iq_meas_A"])

    def test_float32_channels_take_two_slots(self):
        # 2 float32 + 1 int16 channels: 5 of the 4 x 1024 slots a row, 4096 // 5 = 819 rows
        rc, _out, err = self.capture_too_deep
        self.assertEqual(rc, 2, err)
        self.assertIn("at most 819 rows", err)

    def test_stream_above_budget_is_refused_naming_it(self):
        rc, _out, err = self.stream_refused
        self.assertEqual(rc, 1)
        self.assertIn("budget is 9216 B/s", err)      # 80 % of 115200 / 10
        rc, out, err = self.stream_ok
        self.assertEqual(rc, 0, err)
        got = json.loads(out)
        self.assertGreater(got["rows"], 0)
        self.assertAlmostEqual(got["rate_asked_hz"], 100.0)

    def test_exit_codes(self):
        self.assertEqual(self.unknown[0], 2, self.unknown[2])
        self.assertIn("no_such_variable", self.unknown[2])
        self.assertEqual(self.refused[0], 1)
        self.assertIn("speed reference", self.refused[2])
        self.assertEqual(self.readonly[0], 1)
        self.assertEqual(self.quit_rc, 0)
        self.assertEqual(self.p.returncode, 0)

    def test_backup_and_restore_the_writable_variables(self):
        self.assertEqual(self.backup[0], 0, self.backup[2])
        with open(self.backup_path) as f:
            saved = json.load(f)
        self.assertLessEqual({"speed_ref_rpm", "te_cmd_Nm", "ud_ref_V", "uq_ref_V", "method", "mode"}, set(saved))
        self.assertEqual(self.set_te[0], 0, self.set_te[2])
        rc, out, err = self.restore
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out), {"te_cmd_Nm": saved["te_cmd_Nm"]})   # only what differed
        self.assertEqual(json.loads(self.after_restore[1])["te_cmd_Nm"], saved["te_cmd_Nm"])

    def test_no_answer_is_exit_3(self):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]          # nothing listens once closed
        rc, _out, err = tool(port, "--timeout", "0.3", "status")
        self.assertEqual(rc, 3, err)


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class LevelAndPlot(unittest.TestCase):
    """`plot` headless (MPLBACKEND=Agg, a duration limit, the last frame saved) and `level`:
    the next start's build level set over the link and taken by a start."""
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()
        cls.png = os.path.join(cls.tmp, "plot.png")
        # no load: a stopped drive stays at rest, so the next start begins from standstill
        cls.p, cls.port = start_sil(cls.tmp, "--realtime", "1", "--summary", os.devnull,
                                    scenario=SCENARIO.replace("torque_Nm = 0:1", "torque_Nm = 0:0"))
        os.environ["MPLBACKEND"] = "Agg"
        try:
            cls.plot = tool(cls.port, "--json", "plot", "speed_est_rpm", "iq_meas_A", "--rate", "100",
                            "--duration", "1.5", "--png", cls.png)
            cls.plot_frames = tool(cls.port, "--json", "plot", "speed_est_rpm", "--frames", "3")
        finally:
            del os.environ["MPLBACKEND"]
        cls.level_before = tool(cls.port, "--json", "level")
        cls.level_set = tool(cls.port, "--json", "level", "4")
        cls.level_bad = tool(cls.port, "level", "7")
        cls.stop = tool(cls.port, "stop")
        time.sleep(0.3)
        cls.start = tool(cls.port, "start")
        cls.states = []
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            rc, out, _err = tool(cls.port, "--json", "get", "state", "level")
            if rc == 0:
                cls.states.append(json.loads(out))
                if cls.states[-1]["level"] == 4 and cls.states[-1]["state"] == 5:
                    break
            time.sleep(0.2)
        cls.quit_rc, _ = finish(cls.p, cls.port)

    def test_plot_runs_headless_for_its_duration_and_saves_the_frame(self):
        rc, out, err = self.plot
        self.assertEqual(rc, 0, err)
        info = json.loads(out)
        # 1.5 s of a 100 Hz stream at --realtime 1: at most about 150 rows (the first ones
        # may not have come yet); a redraw at least every 0.1 s poll + 0.05 s pause + drawing
        self.assertGreater(info["rows"], 50)
        self.assertLess(info["rows"], 200)
        self.assertGreaterEqual(info["frames"], 2)
        t0, t1 = info["t_s"]
        self.assertGreater(t1, t0)
        with open(self.png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_plot_stops_after_its_frames(self):
        rc, out, err = self.plot_frames
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out)["frames"], 3)

    def test_level_is_set_for_the_next_start_and_taken_by_it(self):
        rc, out, err = self.level_before
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out), {"level": 5, "level_next": 5})    # the scenario's default
        rc, out, err = self.level_set
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out), {"level": 5, "level_next": 4})    # the running start keeps its level
        self.assertEqual(self.stop[0], 0, self.stop[2])
        self.assertEqual(self.start[0], 0, self.start[2])
        # the start took level 4 (torque control at the reduced current limit) and runs (RUN, 5)
        self.assertEqual(self.states[-1], {"state": 5, "level": 4}, self.states)
        self.assertEqual(self.quit_rc, 0)

    def test_a_level_outside_1_to_5_is_a_usage_error(self):
        rc, _out, err = self.level_bad
        self.assertEqual(rc, 2, err)


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class Pty(unittest.TestCase):
    def test_status_and_quit_over_a_pty(self):
        tmp = tempfile.mkdtemp()
        ini = os.path.join(tmp, "link.ini")
        with open(ini, "w") as f:
            f.write(SCENARIO)
        err_path = os.path.join(tmp, "drive_sil.err")
        with open(err_path, "w") as err:
            p = subprocess.Popen([DRIVE_SIL, "--scenario", ini, "--summary", os.devnull, "--link", "pty",
                                  "--realtime", "1"], stdout=subprocess.DEVNULL, stderr=err)
        try:
            line = ""
            deadline = time.monotonic() + 30
            while not line.endswith("\n") and p.poll() is None and time.monotonic() < deadline:
                time.sleep(0.02)
                with open(err_path) as f:
                    line = f.readline()
            self.assertTrue(line.startswith("link on /dev/"), line)
            dev = line.split()[-1]
            env = dict(os.environ, XDG_CACHE_HOME=tempfile.gettempdir())
            r = subprocess.run([DRIVETOOL, "--port", dev, "--json", "status"], capture_output=True, text=True,
                               timeout=60, env=env)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(json.loads(r.stdout)["state_name"], "RUN")
            r = subprocess.run([DRIVETOOL, "--port", dev, "quit"], capture_output=True, text=True, timeout=60,
                               env=env)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(p.wait(timeout=30), 0)
        finally:
            if p.poll() is None:
                p.kill()
                p.wait()


def raw_connect(port):
    """A bare TCP client of drive_sil --link (no drivetool)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=30)
    return s


def read_until_closed(s, limit_s=30.0):
    """Every frame s receives until the drive closes it: [(type, seq, payload)]."""
    from drivetool import codec
    rx = codec.Receiver()
    frames = []
    s.settimeout(limit_s)
    while True:
        try:
            data = s.recv(4096)
        except socket.timeout:
            raise AssertionError("the drive did not close the connection") from None
        except ConnectionResetError:
            break
        if not data:
            break
        frames += rx.feed(data)
    return frames


@unittest.skipUnless(HAVE_SERIAL and os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs pyserial, build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class Clients(unittest.TestCase):
    """Whatever a client does, drive_sil --link runs on: a second client is told the link is
    held and closed at once; a silent one is dropped after [link] idle_timeout_s; a stream killed
    mid-frame, 20 kB of garbage then a close, a client that shuts its sending side after a
    request (and gets its reply): each followed by a client that is served; at the end quit is
    exit 0 with the CSV complete under its name."""
    IDLE_S = 2.0

    @classmethod
    def setUpClass(cls):
        from drivetool import Drive, codec
        cls.tmp = tempfile.mkdtemp()
        cls.csv_path = os.path.join(cls.tmp, "run.csv")
        scenario = SCENARIO + f"[link]\nidle_timeout_s = {cls.IDLE_S:g}\n"
        cls.p, cls.port = start_sil(cls.tmp, "--realtime", "1", "--out", cls.csv_path, scenario=scenario)
        # two clients: the first (kept alive by PINGs) served, the second told at once
        first = Drive(f"socket://127.0.0.1:{cls.port}", cache=False)
        stop = threading.Event()

        def keep_alive():
            while not stop.wait(cls.IDLE_S / 4):
                first.ping()
        t = threading.Thread(target=keep_alive)
        t.start()
        try:
            t0 = time.monotonic()
            cls.second = tool(cls.port, "--timeout", "0.5", "status")
            cls.second_s = time.monotonic() - t0
        finally:
            stop.set()
            t.join()    # one thread on a Drive at a time: its requests must not interleave
        try:
            cls.first_after = first.get("state")
        finally:
            first.close()
        # a silent client: told "idle" and closed after idle_timeout_s, then the next is served
        s = raw_connect(cls.port)
        t0 = time.monotonic()
        cls.silent_frames = read_until_closed(s)
        cls.silent_s = time.monotonic() - t0
        s.close()
        cls.after_silent = tool(cls.port, "--timeout", "10", "--json", "status")
        # a stream killed mid-frame (SIGKILL: the socket reset with the drive's bytes on their way)
        sp = subprocess.Popen([DRIVETOOL, "--port", f"socket://127.0.0.1:{cls.port}", "stream", "iq_meas_A",
                               "id_meas_A", "speed_est_rpm", "te_est_Nm", "--rate", "300", "--duration", "60"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                              env=dict(os.environ, XDG_CACHE_HOME=tempfile.gettempdir()))
        cls.stream_line = sp.stderr.readline()          # "streaming ...": the stream runs
        sp.kill()
        sp.wait()
        sp.stderr.close()
        cls.after_kill = tool(cls.port, "--timeout", "10", "--json", "status")
        # 20 kB of garbage, then a close
        rng = random.Random(29)
        s = raw_connect(cls.port)
        s.sendall(bytes(rng.randrange(256) for _ in range(20000)))
        s.close()
        cls.after_garbage = tool(cls.port, "--timeout", "10", "--json", "status")
        # half-close: HELLO, then no more sending; the reply still comes, then the drive closes
        s = raw_connect(cls.port)
        s.sendall(codec.frame_encode(codec.HELLO, 7))
        s.shutdown(socket.SHUT_WR)
        cls.half_frames = read_until_closed(s)
        s.close()
        cls.quit_rc, cls.quit_err = finish(cls.p, cls.port)

    def test_a_second_client_is_told_the_link_is_held(self):
        rc, _out, err = self.second
        self.assertEqual(rc, 3, err)
        self.assertIn("held by another client", err)
        self.assertLess(self.second_s, 20.0)               # told, not left to time out
        self.assertEqual(self.first_after["state"], 5)      # the first client is still served

    def test_a_silent_client_is_dropped_after_the_idle_timeout(self):
        from drivetool import codec
        notices = [f for f in self.silent_frames if f[0] == codec.NOTICE]
        self.assertEqual(len(notices), 1, self.silent_frames)
        self.assertEqual(notices[0][2][0], codec.NOTICE_IDLE)
        self.assertGreaterEqual(self.silent_s, self.IDLE_S * 0.9)
        rc, out, err = self.after_silent
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out)["state_name"], "RUN")

    def test_a_stream_killed_mid_frame_leaves_the_link_working(self):
        self.assertTrue(self.stream_line.startswith("streaming"), self.stream_line)
        rc, out, err = self.after_kill
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out)["state_name"], "RUN")

    def test_garbage_then_close_leaves_the_link_working(self):
        rc, out, err = self.after_garbage
        self.assertEqual(rc, 0, err)
        self.assertEqual(json.loads(out)["state_name"], "RUN")

    def test_a_half_closed_client_gets_its_reply(self):
        from drivetool import codec
        replies = [f for f in self.half_frames if f[0] == codec.HELLO | codec.REPLY]
        self.assertEqual(len(replies), 1, self.half_frames)
        self.assertEqual(replies[0][1], 7)
        self.assertEqual(replies[0][2][0], codec.ST_OK)

    def test_quit_ends_the_run_with_the_csv_complete(self):
        self.assertEqual(self.quit_rc, 0, self.quit_err)
        self.assertEqual(self.p.returncode, 0)
        self.assertEqual([f for f in os.listdir(self.tmp) if ".tmp" in f], [])
        with open(self.csv_path) as f:
            rows = list(csv.reader(f))
        self.assertGreater(len(rows), 2)
        self.assertEqual(len(rows[-1]), len(rows[0]))       # the last row whole
        self.assertTrue(os.path.exists(os.path.join(self.tmp, "run.resolved.json")))


class Proxy:
    """Forwards TCP connections to target_port through self._pump(src, dst), one thread each
    way; nodelay: TCP_NODELAY both sides (a byte goes on as it comes, as on a UART)."""
    NODELAY = False

    def __init__(self, target_port, rate, seed):
        self.rng = random.Random(seed)
        self.rate = rate
        self.ls = socket.socket()
        self.ls.bind(("127.0.0.1", 0))
        self.ls.listen(4)
        self.port = self.ls.getsockname()[1]
        self.target = target_port
        threading.Thread(target=self._serve, daemon=True).start()

    @staticmethod
    def _close(a, b):
        for s in (a, b):
            try:
                s.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            s.close()

    def _serve(self):
        while True:
            c, _ = self.ls.accept()
            d = socket.create_connection(("127.0.0.1", self.target))
            if self.NODELAY:
                for s in (c, d):
                    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            threading.Thread(target=self._pump, args=(c, d), daemon=True).start()
            threading.Thread(target=self._pump, args=(d, c), daemon=True).start()


class LossyProxy(Proxy):
    """Forwards TCP connections frame by frame (split at each 0x00), spoiling RATE of
    the frames each way, a fifth each: dropped, a bit flipped, duplicated, garbage put
    before it, one byte lost."""

    def __init__(self, target_port, rate, seed):
        self.spoiled = 0
        super().__init__(target_port, rate, seed)

    def _spoil(self, frame):
        if self.rng.random() >= self.rate:
            return frame
        self.spoiled += 1
        k = self.rng.randrange(5)
        i = self.rng.randrange(len(frame))
        if k == 0:
            return b""
        if k == 1:
            b = bytearray(frame)
            b[i] ^= 1 << self.rng.randrange(8)
            return bytes(b)
        if k == 2:
            return frame + frame
        if k == 3:
            return bytes(self.rng.randrange(256) for _ in range(self.rng.randrange(1, 9))) + frame
        return frame[:i] + frame[i + 1:]

    def _pump(self, a, b):
        pending = b""
        try:
            while True:
                data = a.recv(4096)
                if not data:
                    break
                pending += data
                while b"\x00" in pending:
                    frame, pending = pending.split(b"\x00", 1)
                    b.sendall(self._spoil(frame + b"\x00"))
        except OSError:
            pass
        self._close(a, b)


@unittest.skipUnless(HAVE_SERIAL and os.access(DRIVE_SIL, os.X_OK), "needs pyserial and build/host/drive_sil")
class LossyLink(unittest.TestCase):
    WRITES = 40

    def test_every_write_once_and_the_drive_runs_on(self):
        from drivetool import Drive, LinkError, codec
        tmp = tempfile.mkdtemp()
        p, port = start_sil(tmp, "--realtime", "1", "--summary", os.path.join(tmp, "s.json"))
        try:
            proxy = LossyProxy(port, 0.10, seed=7)
            ok, failed, last = 0, 0, None
            d = Drive(f"socket://127.0.0.1:{proxy.port}", cache=False, retries=12)
            before = d.get("link_writes")["link_writes"]
            for k in range(self.WRITES):
                v = 100.0 + k
                try:
                    d.set("te_cmd_Nm", v / 100.0)   # torque reference: unused in speed mode, harmless
                    ok += 1
                    last = v / 100.0
                except LinkError:
                    failed += 1                     # failed cleanly: an exception, no hang
            # a capture uploaded through the same link: pages lost on the way are asked again
            cap = None
            for _ in range(5):
                try:
                    d.capture_arm(["iq_meas_A", "speed_est_rpm"], codec.TRIG_FORCED, None, 0.0, 0.0, 0, 600, 1)
                    while d.capture_status()["state"] != codec.CAP_DONE:
                        pass
                    cap = d.capture_read(d.capture_status())
                    break
                except LinkError:
                    continue
            d.close()
            self.assertIsNotNone(cap, "no capture through the lossy link")
            self.assertGreater(ok, self.WRITES * 3 // 4)
            time.sleep(0.3)
            # a clean connection: the drive counted each write at most once, every acknowledged one
            with Drive(f"socket://127.0.0.1:{port}", cache=False) as c:
                v = c.get("link_writes", "te_cmd_Nm", "state", "link_err_crc", "link_err_framing")
                clean = c.capture_read(c.capture_status())
            self.assertEqual(cap, clean)                                # every page, each where it belongs
            applied = v["link_writes"] - before
            self.assertGreaterEqual(applied, ok)
            self.assertLessEqual(applied, ok + failed)
            if failed == 0:
                self.assertAlmostEqual(v["te_cmd_Nm"], last, places=5)
            self.assertEqual(v["state"], 5)                            # RUN: the drive ran on
            self.assertGreater(proxy.spoiled, 0)
            print(f"lossy link: {proxy.spoiled} frames spoiled, {ok} writes acknowledged, {failed} failed cleanly, "
                  f"{applied} applied", file=sys.stderr)
        finally:
            rc, _ = finish(p, port)
        self.assertEqual(rc, 0)


# The paper motor (drive_sil's defaults), free shaft, started at t = 0 and stopped by the test.
COMM_SCENARIO = """[controller]
method = conventional
mode = speed
[load]
torque_Nm = 0
[run]
duration_s = 0
"""
TABLE1 = {"R_ohm": 3.0, "L_H": 0.011, "psif_Wb": 0.24, "J_kgm2": 0.00129}
COMM_TOL = {"R_ohm": 0.03, "L_H": 0.03, "psif_Wb": 0.03, "J_kgm2": 0.10}


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class Commission(unittest.TestCase):
    def commission(self, *extra):
        tmp = tempfile.mkdtemp()
        scenario = COMM_SCENARIO + "".join(f"[{s}]\n{kv}\n" for s, kv in extra)
        p, port = start_sil(tmp, "--realtime", "0", "--summary", os.devnull, scenario=scenario)
        try:
            rc, _out, err = tool(port, "stop")
            self.assertEqual(rc, 0, err)
            ini = os.path.join(tmp, "out.ini")
            r = tool(port, "--json", "commission", "--ini", ini, timeout=300)
            state = tool(port, "--json", "get", "state", "comm_result", "comm_stage")
        finally:
            finish(p, port)
        return r, ini, state

    def test_commissions_the_paper_motor(self):
        (rc, out, err), ini, _ = self.commission()
        self.assertEqual(rc, 0, err)
        v = json.loads(out)
        for k, truth in TABLE1.items():
            self.assertLess(abs(v[k] / truth - 1.0), COMM_TOL[k], f"{k} {v[k]} against {truth}")
        self.assertEqual(v["pole_pairs"], 3)
        with open(ini) as f:
            text = f.read()
        self.assertIn("[controller]", text)
        for k in ("R_ohm", "L_H", "psif_Wb", "pole_pairs", "J_kgm2", "B_Nms", "encoder_offset_el_rad",
                  "speed_kp_Nms_rad", "speed_ki_Nm_rad", "deadtime_s", "device_drop_V", "untold_deadtime_s"):
            self.assertRegex(text, rf"(?m)^{k} = [-+0-9.e]+$")
        self.assertRegex(text, r"(?m)^\[identify\]\nmode = trusted$")
        print("drivetool commission: " + ", ".join(f"{k} {v[k]:.6g}" for k in v), file=sys.stderr)

    def test_a_reversed_encoder_is_refused_naming_it(self):
        (rc, _out, err), ini, (src, sout, serr) = self.commission(("plant", "encoder_direction = -1"))
        self.assertEqual(rc, 1, err)
        self.assertIn("ENCODER_DIRECTION in stage ENCODER", err)
        self.assertFalse(os.path.exists(ini))
        self.assertEqual(src, 0, serr)
        s = json.loads(sout)
        self.assertEqual((s["state"], s["comm_result"], s["comm_stage"]), (6, 3, 3))   # FAULT, refused, ENCODER


def sim_time(csv_path):
    """The t_s of the last whole row drive_sil has written to csv_path (0 before one)."""
    try:
        with open(csv_path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - 4096))
            lines = f.read().split(b"\n")
    except OSError:
        return 0.0
    for line in reversed(lines[:-1]):      # the last piece may be a row being written
        try:
            return float(line.split(b",", 1)[0])
        except ValueError:
            continue
    return 0.0


def wait_sim(csv_path, t_s, limit_s=120.0):
    """Until drive_sil's simulated time passes t_s (its CSV says so): no wall-time guess."""
    deadline = time.monotonic() + limit_s
    while sim_time(csv_path) < t_s:
        if time.monotonic() > deadline:
            raise AssertionError(f"drive_sil did not reach t = {t_s} s")
        time.sleep(0.05)


def wait_state(port, state, limit_s=60.0):
    """Polls until the drive's state is `state` (a number); returns the last --json status."""
    deadline = time.monotonic() + limit_s
    while True:
        rc, out, err = tool(port, "--json", "status")
        if rc == 0 and json.loads(out)["state"] == state:
            return json.loads(out)
        if time.monotonic() > deadline:
            raise AssertionError(f"state {state} not reached: {out} {err}")
        time.sleep(0.1)


# A drive at rest with a bench's passive load, in speed mode at 0 r/min until the link writes.
BENCH_SCENARIO = """[controller]
method = conventional
mode = speed
[reference]
speed_rpm = 0
[load]
torque_Nm = 0
friction_Nm = 0.05
viscous_Nms = 0.001
[run]
duration_s = 0
log_every = 20
"""
RUN, IDLE, FAULT = 5, 1, 6          # app_state_t
HOST_TIMEOUT_BIT = 0x2000            # APP_WARN_HOST_TIMEOUT (firmware/app/app.h)
# drive_sil's name of it, whole (tools/sil/summary.c): in its line, --summary and .resolved.json
HOST_TIMEOUT_TEXT = "HOST_TIMEOUT (the link's host went quiet: ramped to zero, stopped)"


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class HostTimeout(unittest.TestCase):
    """[link] host_timeout_s = 1: a speed reference written over the link (210 r/min), then no
    frame: 1 s of simulated time later the drive ramps to zero and stops (IDLE) with the warning
    HOST_TIMEOUT, named by drivetool's status, drive_sil's output, --summary and .resolved.json;
    the CSV's speed_ref_rpm is the firmware's command: the written 210, then the ramp. With the
    default (off) a reference written by one drivetool command keeps the drive turning after it.
    Simulated time is read from the CSV: no wall-clock guess."""
    TIMEOUT_S = 1.0
    REF_RPM = 210.0

    @classmethod
    def run_drive(cls, timeout_s):
        tmp = tempfile.mkdtemp()
        out = {"csv": os.path.join(tmp, "run.csv"), "summary": os.path.join(tmp, "s.json"), "tmp": tmp}
        scenario = BENCH_SCENARIO + (f"[link]\nhost_timeout_s = {timeout_s:g}\n" if timeout_s else "")
        out_path = os.path.join(tmp, "drive_sil.out")
        p, port = start_sil(tmp, "--realtime", "1", "--out", out["csv"], "--summary", out["summary"],
                            scenario=scenario, stdout_path=out_path)
        growing = f"{out['csv']}.tmp.{p.pid}"            # drive_sil writes FILE.tmp.PID, renamed at the end
        try:
            wait_sim(growing, 0.3)
            out["set"] = tool(port, "set", f"speed_ref_rpm={cls.REF_RPM:g}")
            t_set = sim_time(growing)
            wait_sim(growing, t_set + 2.0 * (timeout_s or cls.TIMEOUT_S) + 0.5)   # silence
            out["status_json"] = tool(port, "--json", "status")
            out["status"] = tool(port, "status")
            if timeout_s:
                out["stopped"] = wait_state(port, IDLE)
        finally:
            out["quit"] = finish(p, port)
            with open(out_path) as f:
                out["stdout"] = f.read()
        return out

    @classmethod
    def setUpClass(cls):
        cls.on = cls.run_drive(cls.TIMEOUT_S)
        cls.off = cls.run_drive(0.0)

    def test_silence_ramps_to_zero_and_stops_naming_host_timeout(self):
        o = self.on
        self.assertEqual(o["set"][0], 0, o["set"][2])
        st = o["stopped"]
        self.assertEqual(st["state_name"], "IDLE")
        self.assertIn("HOST_TIMEOUT", st["warnings"])
        self.assertEqual(st["flags"] & HOST_TIMEOUT_BIT, HOST_TIMEOUT_BIT)
        self.assertEqual(st["host_timeout_s"], self.TIMEOUT_S)
        self.assertIn("HOST_TIMEOUT", o["status"][1])
        self.assertEqual(o["quit"][0], 0, o["quit"][1])
        self.assertIn("warning " + HOST_TIMEOUT_TEXT, o["stdout"])
        with open(o["summary"]) as f:
            self.assertIn(HOST_TIMEOUT_TEXT, f.read())
        with open(o["csv"].replace(".csv", ".resolved.json")) as f:
            self.assertIn(HOST_TIMEOUT_TEXT, f.read())

    def test_the_csv_reference_is_the_written_one_then_the_ramp(self):
        with open(self.on["csv"]) as f:
            rows = [(float(r["t_s"]), float(r["speed_ref_rpm"]), int(float(r["state"]))) for r in csv.DictReader(f)]
        at_ref = [t for t, ref, _ in rows if abs(ref - self.REF_RPM) < 1e-3]
        self.assertTrue(at_ref, "the written reference never reached the CSV")
        t_ref = at_ref[0]
        # held at the written value at least the timeout, then ramped down, never back up; the
        # timeout runs from the write, which the first row showing it follows by up to a row
        row_s = rows[1][0] - rows[0][0]
        down = [t for t, ref, _ in rows if t > t_ref and ref < self.REF_RPM - 1e-3]
        self.assertTrue(down)
        self.assertGreaterEqual(down[0] - t_ref, self.TIMEOUT_S - row_s)
        after = [ref for t, ref, _ in rows if t >= down[0]]
        self.assertTrue(all(b <= a + 1e-6 for a, b in zip(after, after[1:])))
        self.assertEqual(rows[-1][2], IDLE)
        self.assertLess(abs(rows[-1][1]), 1e-6)

    def test_off_by_default_a_written_reference_outlives_the_command(self):
        o = self.off
        self.assertEqual(o["set"][0], 0, o["set"][2])
        st = json.loads(o["status_json"][1])
        self.assertEqual(st["state_name"], "RUN")
        self.assertEqual(st["host_timeout_s"], 0.0)
        self.assertNotIn("HOST_TIMEOUT", st["warnings"])
        self.assertLess(abs(st["speed_est_rpm"] - self.REF_RPM), 0.05 * self.REF_RPM)
        self.assertIn("host timeout off", o["status"][1])


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class Refusals(unittest.TestCase):
    """Actions the state makes do nothing are refused naming it (exit 1): with the bus surged
    to 450 V (OVERVOLTAGE latched, its cause staying) start, reset-fault and commission name
    OVERVOLTAGE and the drive stays in FAULT; a commission while running names RUN."""

    @classmethod
    def setUpClass(cls):
        tmp = tempfile.mkdtemp()
        p, port = start_sil(tmp, "--realtime", "1", "--summary", os.devnull, scenario=BENCH_SCENARIO)
        try:
            wait_state(port, RUN)
            cls.comm_running = tool(port, "commission")
        finally:
            finish(p, port)
        tmp = tempfile.mkdtemp()
        scenario = BENCH_SCENARIO + "[faults]\nvdc_surge_s = 0.2\nvdc_surge_V = 450\n"
        p, port = start_sil(tmp, "--realtime", "1", "--summary", os.devnull, scenario=scenario)
        try:
            wait_state(port, FAULT)
            cls.start = tool(port, "start")
            cls.reset = tool(port, "reset-fault")
            cls.comm_faulted = tool(port, "commission")
            cls.after = tool(port, "--json", "get", "state", "fault", "fault_present")
        finally:
            finish(p, port)

    def test_start_in_fault_names_the_fault(self):
        rc, _out, err = self.start
        self.assertEqual(rc, 1, err)
        self.assertIn("OVERVOLTAGE", err)

    def test_reset_fault_with_the_cause_present_names_it(self):
        rc, _out, err = self.reset
        self.assertEqual(rc, 1, err)
        self.assertIn("OVERVOLTAGE", err)
        self.assertEqual(json.loads(self.after[1]), {"state": FAULT, "fault": 5, "fault_present": 5})

    def test_commission_names_the_fault_or_the_state(self):
        rc, _out, err = self.comm_faulted
        self.assertEqual(rc, 1, err)
        self.assertIn("OVERVOLTAGE", err)
        rc, _out, err = self.comm_running
        self.assertEqual(rc, 1, err)
        self.assertIn("RUN", err)


PARAM_KEYS = ("R_ohm", "L_H", "psif_Wb", "pole_pairs", "J_kgm2", "B_Nms", "encoder_offset_el_rad",
              "speed_kp_Nms_rad", "speed_ki_Nm_rad", "te_max_Nm", "i_limit_A", "deadtime_s", "device_drop_V")


def f32(x):
    """x rounded to float32, as the drive holds it."""
    import struct
    return struct.unpack("<f", struct.pack("<f", x))[0]


def read_ini_controller(path):
    import configparser
    cp = configparser.ConfigParser(inline_comment_prefixes=(";",))
    cp.optionxform = str            # the keys as written: R_ohm, not r_ohm
    cp.read(path)
    return {k: float(v) for k, v in cp["controller"].items()}


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class Parameters(unittest.TestCase):
    """The controller's parameters on the link under the scenario keys: refused while running,
    written while stopped and read back; out of the scenario key's own range refused with the
    range named (drive_sil refuses the same key at the same bound); `backup` an INI [controller]
    section drive_sil accepts, holding every parameter as the drive reads it; `restore` puts
    them back exactly (float32) and is all or nothing: one value out of range, nothing written."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()
        p, port = start_sil(cls.tmp, "--realtime", "1", "--summary", os.devnull, scenario=BENCH_SCENARIO)
        cls.ini = os.path.join(cls.tmp, "backup.ini")
        cls.bad_ini = os.path.join(cls.tmp, "bad.ini")
        try:
            wait_state(port, RUN)
            cls.running = tool(port, "set", "speed_kp_Nms_rad=0.4")
            cls.restore_running = None
            cls.stop = tool(port, "stop")
            wait_state(port, IDLE)
            cls.backup = tool(port, "backup", cls.ini)
            cls.before = tool(port, "--json", "get", *PARAM_KEYS)
            cls.restore_running_ini = cls.ini
            cls.set_kp = tool(port, "set", "speed_kp_Nms_rad=0.4", "J_kgm2=0.002")
            cls.after_set = tool(port, "--json", "get", "speed_kp_Nms_rad", "J_kgm2")
            cls.out_of_range = tool(port, "set", "R_ohm=1e9")
            cls.fraction = tool(port, "set", "pole_pairs=2.5")
            # all or nothing: a valid change and a value out of range
            with open(cls.ini) as f:
                text = f.read()
            text = re.sub(r"(?m)^speed_ki_Nm_rad = .*$", "speed_ki_Nm_rad = 33", text)
            text = re.sub(r"(?m)^R_ohm = .*$", "R_ohm = 1e9", text)
            with open(cls.bad_ini, "w") as f:
                f.write(text)
            cls.restore_bad = tool(port, "restore", cls.bad_ini)
            cls.after_bad = tool(port, "--json", "get", *PARAM_KEYS)
            cls.restore = tool(port, "--json", "restore", cls.ini)
            cls.after_restore = tool(port, "--json", "get", *PARAM_KEYS)
        finally:
            cls.quit = finish(p, port)
        cls.check_backup = subprocess.run([DRIVE_SIL, "--scenario", cls.ini, "--check"], capture_output=True,
                                          text=True, timeout=60)
        ini = os.path.join(cls.tmp, "r.ini")
        with open(ini, "w") as f:
            f.write(BENCH_SCENARIO.replace("duration_s = 0", "duration_s = 0.1"))
        cls.check_bad = subprocess.run([DRIVE_SIL, "--scenario", ini, "--check", "--set", "controller.R_ohm=1e9"],
                                       capture_output=True, text=True, timeout=60)

    def test_refused_while_running(self):
        rc, _out, err = self.running
        self.assertEqual(rc, 1, err)
        self.assertIn("stopped", err)

    def test_written_while_stopped_and_read_back(self):
        self.assertEqual(self.stop[0], 0, self.stop[2])
        self.assertEqual(self.set_kp[0], 0, self.set_kp[2])
        self.assertEqual(json.loads(self.after_set[1]), {"speed_kp_Nms_rad": f32(0.4), "J_kgm2": f32(0.002)})

    def test_the_scenario_keys_range_on_both_sides(self):
        rc, _out, err = self.out_of_range
        self.assertEqual(rc, 1, err)
        self.assertIn("R_ohm", err)
        self.assertIn("1000", err)                       # the range's top (LINK_PARAM_R_OHM_HI)
        self.assertNotEqual(self.check_bad.returncode, 0)
        self.assertIn("R_ohm", self.check_bad.stderr)
        self.assertIn("1000", self.check_bad.stderr)     # drive_sil names the same bound
        self.assertEqual(self.fraction[0], 2, self.fraction[2])

    def test_backup_is_a_controller_section_drive_sil_accepts(self):
        self.assertEqual(self.backup[0], 0, self.backup[2])
        saved = read_ini_controller(self.ini)
        self.assertEqual(set(saved), set(PARAM_KEYS))
        before = json.loads(self.before[1])
        for k in PARAM_KEYS:
            self.assertEqual(f32(saved[k]), before[k], k)        # every value, exact as float32
        self.assertEqual(self.check_backup.returncode, 0, self.check_backup.stderr)

    def test_restore_is_exact_and_all_or_nothing(self):
        rc, _out, err = self.restore_bad
        self.assertEqual(rc, 2, err)                     # the file's value checked first: nothing written
        self.assertIn("R_ohm", err)
        self.assertIn("1000", err)
        after_set = json.loads(self.after_set[1])
        bad = json.loads(self.after_bad[1])
        self.assertEqual(bad["speed_ki_Nm_rad"], json.loads(self.before[1])["speed_ki_Nm_rad"])  # not written
        self.assertEqual(bad["speed_kp_Nms_rad"], after_set["speed_kp_Nms_rad"])
        rc, out, err = self.restore
        self.assertEqual(rc, 0, err)
        self.assertEqual(set(json.loads(out)), {"speed_kp_Nms_rad", "J_kgm2"})   # only what differed
        self.assertEqual(json.loads(self.after_restore[1]), json.loads(self.before[1]))
        self.assertEqual(self.quit[0], 0, self.quit[1])


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class DailyUse(unittest.TestCase):
    """drivetool as a daily tool: every command's help names its options' defaults; names, not
    numbers, unless --json (before or after the command); DRIVETOOL_PORT for --port; an integer
    refuses a fraction (exit 2); Ctrl-C ends a stream with exit 130 and no traceback; list's
    ranges (states 0-10, faults 0-28) and capture formats as a capture reports them."""
    COMMANDS = ("status", "list", "get", "set", "start", "stop", "reset-fault", "quit", "commission", "level",
                "stream", "capture", "plot", "backup", "restore")

    @classmethod
    def setUpClass(cls):
        cls.helps = {c: subprocess.run([DRIVETOOL, c, "--help"], capture_output=True, text=True, timeout=60)
                     for c in cls.COMMANDS}
        cls.top_help = subprocess.run([DRIVETOOL, "--help"], capture_output=True, text=True, timeout=60)
        tmp = tempfile.mkdtemp()
        p, port = start_sil(tmp, "--realtime", "1", "--summary", os.devnull, scenario=BENCH_SCENARIO)
        env = dict(os.environ, XDG_CACHE_HOME=tempfile.gettempdir(), DRIVETOOL_PORT=f"socket://127.0.0.1:{port}")
        try:
            wait_state(port, RUN)

            def run(*args, **kw):
                r = subprocess.run([DRIVETOOL, *args], capture_output=True, text=True, timeout=60, env=env, **kw)
                return r.returncode, r.stdout, r.stderr
            cls.names = run("get", "state", "method", "mode")
            cls.numbers = run("get", "--json", "state", "method", "mode")
            cls.numbers_before = run("--json", "get", "state", "method", "mode")
            cls.fraction = run("set", "method=1.7")
            cls.by_name = run("set", "speed_ref_rpm=50")
            cls.list = run("--json", "list")
            cls.list_text = run("list")
            cls.cap = run("--json", "capture", "L_est_H", "iq_meas_A", "--trigger", "forced", "--samples", "10")
            sp = subprocess.Popen([DRIVETOOL, "stream", "speed_est_rpm", "--rate", "50", "--duration", "60"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
            cls.stream_line = sp.stderr.readline()
            sp.send_signal(2)                            # SIGINT: Ctrl-C
            cls.sigint_rc = sp.wait(timeout=30)
            cls.sigint_err = sp.stderr.read()
            sp.stderr.close()
        finally:
            finish(p, port)

    def test_every_command_has_help_with_its_defaults(self):
        self.assertEqual(self.top_help.returncode, 0)
        self.assertIn("DRIVETOOL_PORT", self.top_help.stdout)
        for c, r in self.helps.items():
            self.assertEqual(r.returncode, 0, (c, r.stderr))
            self.assertIn(f"usage: drivetool {c}", r.stdout)
        self.assertIn("(default: 1000)", self.helps["capture"].stdout)          # --samples
        self.assertIn("(default: forced)", self.helps["capture"].stdout)        # --trigger
        self.assertIn("(default: 120.0)", self.helps["commission"].stdout)      # --wait

    def test_names_unless_json_before_or_after_the_command(self):
        rc, out, err = self.names
        self.assertEqual(rc, 0, err)
        self.assertIn("state RUN", out)
        self.assertIn("method conventional", out)
        self.assertIn("mode speed", out)
        for rc, out, err in (self.numbers, self.numbers_before):
            self.assertEqual(rc, 0, err)
            self.assertEqual(json.loads(out), {"state": RUN, "method": 0, "mode": 2})
        self.assertEqual(self.by_name[0], 0, self.by_name[2])                   # DRIVETOOL_PORT served it

    def test_an_integer_refuses_a_fraction(self):
        rc, _out, err = self.fraction
        self.assertEqual(rc, 2, err)
        self.assertIn("whole number", err)

    def test_ctrl_c_is_exit_130_without_a_traceback(self):
        self.assertTrue(self.stream_line.startswith("streaming"), self.stream_line)
        self.assertEqual(self.sigint_rc, 130, self.sigint_err)
        self.assertNotIn("Traceback", self.sigint_err)

    def test_list_ranges_and_capture_formats(self):
        rc, out, err = self.list
        self.assertEqual(rc, 0, err)
        table = {v["name"]: v for v in json.loads(out)}
        self.assertEqual((table["state"]["min"], table["state"]["max"]), (0, 10))
        # the highest fault is RSID_INVERTER (30), the last name drivetool has for one
        from drivetool import drive
        self.assertEqual((table["fault"]["min"], table["fault"]["max"]), (0, 30))
        self.assertEqual(drive.FAULTS[29], "BUS_CHARGED")
        self.assertEqual(drive.FAULTS[30], "RSID_INVERTER")
        self.assertEqual(len(drive.FAULTS), 31)
        self.assertEqual((table["comm_stage"]["min"], table["comm_stage"]["max"]), (0, 7))   # INVERTER the last
        rc, out, err = self.cap
        self.assertEqual(rc, 0, err)
        formats = json.loads(out)["format"]
        self.assertEqual(formats, {"L_est_H": "float32", "iq_meas_A": "int16"})
        self.assertEqual(formats, {n: table[n]["capture"] for n in formats})
        text = {line.split()[0]: line for line in self.list_text[1].splitlines()[1:]}
        self.assertIn("float32", text["L_est_H"])
        self.assertIn("int16", text["iq_meas_A"])
        self.assertIn("[0, 10]", text["state"])


class ByteDropProxy(Proxy):
    """Forwards TCP connections byte by byte, dropping each byte with probability RATE each way
    (a noisy line: a lost byte spoils the frame it falls in). TCP_NODELAY both sides: a byte
    goes on as it comes, as on a UART."""
    NODELAY = True

    def __init__(self, target_port, rate, seed):
        self.dropped = 0
        super().__init__(target_port, rate, seed)

    def _pump(self, a, b):
        try:
            while True:
                data = a.recv(4096)
                if not data:
                    break
                kept = bytes(x for x in data if self.rng.random() >= self.rate)
                self.dropped += len(data) - len(kept)
                if kept:
                    b.sendall(kept)
        except OSError:
            pass
        self._close(a, b)


@unittest.skipUnless(os.access(DRIVE_SIL, os.X_OK) and os.access(DRIVETOOL, os.X_OK),
                     "needs build/host/drive_sil and build/venv/bin/drivetool (make drivetool)")
class LossyCapture(unittest.TestCase):
    """A capture of 1000 rows of two channels, armed (`capture --arm`) and fetched (`capture
    --fetch`) through a line dropping 2 % of the bytes each way at 115200 baud: complete, every
    row equal to the same capture fetched over a clean connection."""
    RATE = 0.02

    def test_arm_and_fetch_over_a_lossy_line(self):
        tmp = tempfile.mkdtemp()
        cache = tempfile.mkdtemp()
        p, port = start_sil(tmp, "--realtime", "1", "--summary", os.devnull, scenario=BENCH_SCENARIO)
        lossy_csv, clean_csv = os.path.join(tmp, "lossy.csv"), os.path.join(tmp, "clean.csv")
        try:
            wait_state(port, RUN)
            self.assertEqual(tool(port, "list", cache=cache)[0], 0)      # the table cached: fewer requests lossy
            proxy = ByteDropProxy(port, self.RATE, seed=29)
            arm = tool(proxy.port, "--retries", "30", "capture", "--arm", "iq_meas_A", "speed_est_rpm",
                       "--trigger", "forced", "--samples", "1000", cache=cache)
            self.assertEqual(arm[0], 0, arm[2])
            t0 = time.monotonic()
            fetch = tool(proxy.port, "--retries", "30", "--json", "capture", "--fetch", "--csv", lossy_csv,
                         cache=cache, timeout=300)
            took = time.monotonic() - t0
            self.assertEqual(fetch[0], 0, fetch[2])
            clean = tool(port, "capture", "--fetch", "--csv", clean_csv, cache=cache)
            self.assertEqual(clean[0], 0, clean[2])
        finally:
            finish(p, port)
        with open(lossy_csv) as f:
            lossy = list(csv.reader(f))
        with open(clean_csv) as f:
            ok = list(csv.reader(f))
        self.assertEqual(len(ok), 1001)
        self.assertEqual(lossy, ok)
        self.assertGreater(proxy.dropped, 0)
        print(f"capture over a 2 % byte-loss line: 1000 rows x 2 channels in {took:.1f} s, "
              f"{proxy.dropped} bytes dropped", file=sys.stderr)


if __name__ == "__main__":
    unittest.main()

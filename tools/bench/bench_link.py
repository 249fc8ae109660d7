#!/usr/bin/env python3
"""bench_link.py DRIVE_SIL - the bytes per second drivetool gets over
drive_sil --link at 115200 and 937500 baud (--realtime 1, the line paced in
simulated time): a forced capture of 4 channels x 1024 rows uploaded with
CAPTURE_READ, the bytes received over the drive's periods spent (PING's
period count before and after), as a share of the line (baud / 10 B/s);
then the fastest stream of 4 variables the 80 % budget accepts. Prints
figures; asserts nothing (make bench)."""
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "drivetool"))
from drivetool import Drive, Refused, codec  # noqa: E402

SCENARIO = "[plant]\nmodel = averaged\n[reference]\nspeed_rpm = 0:500\n[run]\nduration_s = 0\n"
CHANNELS = ["iq_meas_A", "id_meas_A", "speed_est_rpm", "te_est_Nm"]
ROWS = 1024


class CountingPort:
    def __init__(self, port):
        self.port, self.bytes = port, 0

    def read(self, n):
        b = self.port.read(n)
        self.bytes += len(b)
        return b

    def __getattr__(self, name):
        return getattr(self.port, name)


def start(tmp, baud):
    ini = os.path.join(tmp, "bench.ini")
    with open(ini, "w") as f:
        f.write(SCENARIO)
    err = os.path.join(tmp, f"err{baud}")
    with open(err, "w") as e:
        p = subprocess.Popen([sys.argv[1], "--scenario", ini, "--summary", os.devnull, "--link", "tcp:0",
                              "--baud", str(baud), "--realtime", "1"], stdout=subprocess.DEVNULL, stderr=e)
    for _ in range(500):
        with open(err) as f:
            line = f.readline()
        if line.endswith("\n"):
            return p, int(line.rsplit(":", 1)[1])
        time.sleep(0.01)
    p.kill()
    raise SystemExit("bench_link: drive_sil did not listen")


def bench(baud):
    tmp = tempfile.mkdtemp()
    p, port = start(tmp, baud)
    try:
        d = Drive(f"socket://127.0.0.1:{port}", baud=baud, cache=False)
        ts = d.info["Ts_s"]
        d.capture_arm(CHANNELS, codec.TRIG_FORCED, None, 0.0, 0.0, 0, ROWS, 1)
        while True:
            st = d.capture_status()
            if st["state"] == codec.CAP_DONE:
                break
        d.port = CountingPort(d.port)
        t0 = d.ping()["ticks"]
        d.capture_read(st)
        t1 = d.ping()["ticks"]
        got = d.port.bytes / ((t1 - t0) * ts)
        line = baud / 10.0
        print(f"bench-link: {baud:>7} baud: capture upload {got:8.0f} B/s of the line's {line:6.0f} B/s "
              f"({100 * got / line:4.1f} %), {ROWS} rows x {len(CHANNELS)} int16 in {(t1 - t0) * ts:.3f} s")
        dec = 1
        while True:
            try:
                need, budget = d.stream_set(CHANNELS, dec)
                break
            except Refused:
                dec += 1
        d.stream_set([], 1)
        print(f"bench-link: {baud:>7} baud: fastest stream of {len(CHANNELS)} variables: every {dec} periods, "
              f"{1 / (dec * ts):6.0f} rows/s ({need} of {budget} B/s)")
        d.action(codec.ACT_QUIT)
        d.close()
    finally:
        try:
            p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            p.kill()


def main():
    for baud in (115200, 937500):
        bench(baud)


if __name__ == "__main__":
    main()

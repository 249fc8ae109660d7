#!/usr/bin/env python3
"""fuzz_link_socket.py DRIVE_SIL ACTIONS SEED - drive_sil --link's socket
layer (tools/sil/link_sil.c) under random clients: ACTIONS seeded draws of
  serve     a client sends a request and gets its reply (a held link is tried
            again, as drivetool does, until the last client's close is seen)
  partial   part of a frame, then a close
  garbage   1 B .. 20 kB of random bytes, then a close
  reset     bytes, then a reset (SO_LINGER 0)
  silent    a connection that sends nothing, then a close
  half      a request, then the sending side shut: the reply must still come
  second    a served client and a second one: the second gets the notice
            "held" at once and is closed, the first is still served
  second_gone  a second client that sends and closes while the first is served,
            then the first closes (drive_sil used to die of SIGPIPE here)
  stream    a stream asked for, a few frames read, then a reset mid-frame
  noread    a stream asked for and never read, then a close
After every action drive_sil must be alive; at the end a client is served,
ACTION quit ends the run with exit 0 and the CSV is complete under its name.
Prints "fuzz-link-socket: N actions, S s, N findings"; exit 1 on a finding.
Standard library only (drivetool's codec from tools/drivetool)."""
import os
import random
import socket
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "drivetool"))
from drivetool import codec  # noqa: E402

SCENARIO = "[plant]\nmodel = averaged\n[reference]\nspeed_rpm = 0:300\n[run]\nduration_s = 0\nlog_every = 100\n" \
           "[link]\nidle_timeout_s = 5\n"
REPLY_S = 10.0          # a reply comes within this (wall time, a busy machine)
HELD_RETRY_S = 0.05
CONNECT_S = 10.0        # a held link is tried again this long (the last client's close on its way)
GARBAGE_MAX = 20000
STREAM_IDS = (3, 10, 11, 7)     # speed_est_rpm, id_meas_A, iq_meas_A, te_est_Nm (firmware/link/link_vars.h)
STREAM_DECIMATE = 40


class Finding(Exception):
    pass


def start(drive_sil, tmp):
    ini = os.path.join(tmp, "fuzz.ini")
    with open(ini, "w") as f:
        f.write(SCENARIO)
    err = os.path.join(tmp, "drive_sil.err")
    with open(err, "w") as e:
        p = subprocess.Popen([drive_sil, "--scenario", ini, "--link", "tcp:0", "--realtime", "1",
                              "--out", os.path.join(tmp, "run.csv")], stdout=subprocess.DEVNULL, stderr=e)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and p.poll() is None:
        with open(err) as f:
            line = f.readline()
        if line.startswith("listening on 127.0.0.1:") and line.endswith("\n"):
            return p, int(line.rsplit(":", 1)[1])
        time.sleep(0.02)
    p.kill()
    raise Finding("drive_sil did not listen")


def frames_until(s, want, limit_s=REPLY_S):
    """Frames read from s until want(frames) holds, the peer closes, or limit_s: (frames, closed)."""
    rx = codec.Receiver()
    frames = []
    deadline = time.monotonic() + limit_s
    while not want(frames):
        left = deadline - time.monotonic()
        if left <= 0:
            return frames, False
        s.settimeout(left)
        try:
            data = s.recv(4096)
        except socket.timeout:
            return frames, False
        except OSError:
            return frames, True
        if not data:
            return frames, True
        frames += rx.feed(data)
    return frames, False


def reply_of(ftype, seq):
    return lambda fs: any(f[0] == (ftype | codec.REPLY) and f[1] == seq for f in fs)


def held(fs):
    return any(f[0] == codec.NOTICE for f in fs)


def connect(port):
    return socket.create_connection(("127.0.0.1", port), timeout=REPLY_S)


def reset_close(s):
    s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    s.close()


def served(port, rng, ftype=None):
    """A client whose request is answered (retrying while the link is held); the open socket."""
    deadline = time.monotonic() + CONNECT_S
    while True:
        s = connect(port)
        seq = rng.randrange(1, 256)
        ftype = ftype or rng.choice([codec.HELLO, codec.PING, codec.CAPTURE_STATUS])
        s.sendall(codec.frame_encode(ftype, seq))
        fs, _closed = frames_until(s, lambda f: reply_of(ftype, seq)(f) or held(f))
        if reply_of(ftype, seq)(fs):
            return s
        s.close()
        if not held(fs) or time.monotonic() > deadline:
            raise Finding(f"no reply to request 0x{ftype:02x} (frames {fs})")
        time.sleep(HELD_RETRY_S)


def a_partial(port, rng):
    s = connect(port)
    f = codec.frame_encode(codec.READ, rng.randrange(1, 256), struct.pack("<H", rng.randrange(40)))
    s.sendall(f[:rng.randrange(1, len(f))])
    s.close()


def a_garbage(port, rng):
    s = connect(port)
    s.sendall(bytes(rng.randrange(256) for _ in range(rng.randrange(1, GARBAGE_MAX))))
    s.close()


def a_reset(port, rng):
    s = connect(port)
    s.sendall(bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300))))
    reset_close(s)


def a_silent(port, rng):
    s = connect(port)
    time.sleep(rng.random() * 0.2)
    s.close()


def a_half(port, rng):
    deadline = time.monotonic() + CONNECT_S
    while True:
        s = connect(port)
        seq = rng.randrange(1, 256)
        s.sendall(codec.frame_encode(codec.HELLO, seq))
        s.shutdown(socket.SHUT_WR)
        fs, closed = frames_until(s, lambda f: False)
        s.close()
        if reply_of(codec.HELLO, seq)(fs) and closed:
            return
        if not held(fs) or time.monotonic() > deadline:
            raise Finding(f"half-closed client: no reply, or not closed (frames {fs}, closed {closed})")
        time.sleep(HELD_RETRY_S)


def a_second(port, rng):
    first = served(port, rng)
    second = connect(port)
    fs, closed = frames_until(second, lambda f: False)
    second.close()
    notices = [f for f in fs if f[0] == codec.NOTICE]
    if len(notices) != 1 or notices[0][2][0] != codec.NOTICE_HELD or not closed:
        raise Finding(f"a second client was not told the link is held and closed (frames {fs})")
    seq = rng.randrange(1, 256)
    first.sendall(codec.frame_encode(codec.PING, seq))
    if not reply_of(codec.PING, seq)(frames_until(first, reply_of(codec.PING, seq))[0]):
        raise Finding("the first client is no longer served after a second one came")
    first.close()


def a_second_gone(port, rng):
    first = served(port, rng)
    second = connect(port)
    second.sendall(codec.frame_encode(codec.HELLO, 1) * 4)
    second.close()
    time.sleep(rng.random() * 0.1)
    first.close()


def a_stream(port, rng, read_some=True):
    s = served(port, rng, codec.HELLO)
    n = rng.randrange(1, len(STREAM_IDS) + 1)
    s.sendall(codec.frame_encode(codec.STREAM_SET, 9, struct.pack("<H", STREAM_DECIMATE) +
                                 b"".join(struct.pack("<H", i) for i in STREAM_IDS[:n])))
    if read_some:
        frames_until(s, lambda fs: sum(f[0] == codec.STREAM for f in fs) >= rng.randrange(1, 5))
        reset_close(s)
    else:
        time.sleep(rng.random() * 0.5)
        s.close()


def a_noread(port, rng):
    a_stream(port, rng, read_some=False)


def a_serve(port, rng):
    served(port, rng).close()


ACTIONS = [a_serve, a_partial, a_garbage, a_reset, a_silent, a_half, a_second, a_second_gone, a_stream, a_noread]


def main(argv):
    drive_sil, n, seed = argv[1], int(argv[2]), int(argv[3])
    rng = random.Random(seed)
    tmp = tempfile.mkdtemp()
    t0 = time.monotonic()
    p, port = start(drive_sil, tmp)
    done = 0
    try:
        for done in range(1, n + 1):
            act = rng.choice(ACTIONS)
            act(port, rng)
            if p.poll() is not None:
                raise Finding(f"drive_sil ended (exit {p.returncode}) after action {done}, {act.__name__}")
        s = served(port, rng)
        s.sendall(codec.frame_encode(codec.ACTION, 5, bytes([codec.ACT_QUIT])))
        frames_until(s, lambda f: False)
        s.close()
        rc = p.wait(timeout=30)
        if rc != 0:
            raise Finding(f"quit: drive_sil exit {rc}")
        left = [f for f in os.listdir(tmp) if ".tmp" in f]
        if left or not os.path.exists(os.path.join(tmp, "run.csv")):
            raise Finding(f"the CSV is not complete under its name ({sorted(os.listdir(tmp))})")
    except (Finding, OSError, subprocess.TimeoutExpired) as e:
        if p.poll() is None:
            p.kill()
        with open(os.path.join(tmp, "drive_sil.err")) as f:
            sys.stderr.write(f.read()[-2000:])
        print(f"fuzz-link-socket: FINDING at action {done} (seed {seed}): {e}")
        print(f"fuzz-link-socket: {done} actions, {time.monotonic() - t0:.0f} s, 1 findings")
        return 1
    print(f"fuzz-link-socket: {n} actions, {time.monotonic() - t0:.0f} s, 0 findings")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

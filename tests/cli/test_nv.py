#!/usr/bin/env python3
"""test_nv.py DRIVE_SIL DRIVETOOL - drive_sil --nv FILE (tools/sil/nv_file.h):
the parameter sector kept in FILE, read before the run as the board reads
its flash at start-up (firmware/params/nv_store.h), written by the link's
save (firmware/link/link_nv.h, drivetool save).

The parameter store's round trip, through drivetool: a run with
--nv FILE and --link (FILE absent: NV_EMPTY on stderr) is stopped,
speed_kp_Nms_rad set, saved, quit; a new run with --nv FILE says what it
loaded and reads the value back over the link (nv_status VALID); one
corrupted byte of the block: NV_INVALID on stderr and the scenario's own
speed_kp; a save while running or without a store is refused (exit 1).

The sector images of the format checks are built here from nv_store.h's
words, with this file's own CRC32_PRIME, key ids and table id (the link
table's keys read from firmware/link/link_params.h), independent of the
firmware's code: a block of two of the table's parameters is loaded; a
block of another table (the table without its last key), of a key not in
it, or of a value beyond its bound is NV_INVALID naming why where it can;
a FILE of the wrong size exits 2. Standard library only (drivetool is run
as a program).
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

from checks import Checks

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
WORDS = 0x8000
MAGIC, VERSION = 0x4E56, 2
HEADER, PAIR, CRC = 4, 3, 2
KP = 0.0421                   # the speed PI's kp saved: not the paper motor's derived one
VALID = 2                     # nv_status (link_nv_status_t)
TIMEOUT_S = 60

check = Checks("test_nv")


def crc32_prime(octets):
    """CRC32_PRIME: poly 0x04C11DB7, init 0, MSB first, no reflection, no final XOR."""
    c = 0
    for o in octets:
        c ^= o << 24
        for _ in range(8):
            c = ((c << 1) ^ 0x04C11DB7) & 0xFFFFFFFF if c & 0x80000000 else (c << 1) & 0xFFFFFFFF
    return c


def words_octets(words):
    return [b for w in words for b in (w & 0xFF, w >> 8)]


def fold(c):
    return (c >> 16) ^ (c & 0xFFFF)


def key_id(name):
    return fold(crc32_prime(name.encode()))


def link_keys():
    """The link's parameter table, its keys in order (the X list of link_params.h)."""
    with open(os.path.join(ROOT, "firmware", "link", "link_params.h")) as f:
        text = f.read()
    body = re.search(r"#define LINK_PARAMS\(X\)(.*?)\n\n", text, re.S).group(1)
    return re.findall(r'X\(\w+, "(\w+)"', body)


def table_id(keys):
    return fold(crc32_prime(words_octets([key_id(k) for k in keys])))


def block(pairs, table):
    w = [MAGIC, VERSION, HEADER + CRC + PAIR * len(pairs), table]
    for name, v in pairs:
        u = struct.unpack("<I", struct.pack("<f", v))[0]
        w += [key_id(name), u & 0xFFFF, u >> 16]
    c = crc32_prime(words_octets(w))
    return w + [c & 0xFFFF, c >> 16]


def image(words):
    w = words + [0xFFFF] * (WORDS - len(words))
    return bytes(words_octets(w))


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


def run(drive_sil, scen, nv, out):
    r = subprocess.run([drive_sil, "--scenario", scen, "--set", "run.duration_s=0.002", "--nv", nv, "--out", out],
                       capture_output=True, text=True, timeout=TIMEOUT_S)
    res = None
    if os.path.exists(out[:-4] + ".resolved.json"):
        with open(out[:-4] + ".resolved.json") as f:
            res = json.load(f)["keys"]
    return r, res


class Live:
    """drive_sil --link tcp:0 at real time (--nv FILE when given) and drivetool on its port; stderr kept."""

    def __init__(self, drive_sil, drivetool, scen, nv, tmp):
        self.drivetool, self.tmp = drivetool, tmp
        extra = ["--nv", nv] if nv else []
        self.p = subprocess.Popen([drive_sil, "--scenario", scen, "--link", "tcp:0", "--realtime", "1",
                                   "--summary", os.path.join(tmp, "live.json"), *extra],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.err = ""
        for line in self.p.stderr:
            self.err += line
            if line.startswith("listening on 127.0.0.1:"):
                self.port = int(line.rsplit(":", 1)[1])
                return
        self.p.wait()
        raise RuntimeError("drive_sil did not listen: " + self.err)

    def tool(self, *args):
        r = subprocess.run([self.drivetool, "--port", "socket://127.0.0.1:%d" % self.port, *args],
                           capture_output=True, text=True, timeout=TIMEOUT_S,
                           env=dict(os.environ, XDG_CACHE_HOME=self.tmp))
        return r.returncode, r.stdout, r.stderr

    def quit(self):
        rc = self.tool("quit")[0]
        self.err += self.p.communicate(timeout=TIMEOUT_S)[1]
        return rc == 0 and self.p.returncode == 0


def round_trip(drive_sil, drivetool, tmp, scen):
    nv = os.path.join(tmp, "saved.bin")
    live = Live(drive_sil, drivetool, scen, nv, tmp)
    running = live.tool("save")
    stop = live.tool("stop")[0]
    kp = live.tool("set", "speed_kp_Nms_rad=%g" % KP)[0]
    saved = live.tool("save")
    ok = live.quit()
    check("NV_EMPTY" in live.err and running[0] == 1 and "not stopped" in running[2],
          "link run, no FILE: NV_EMPTY on stderr; a save while running refused naming it (%s)"
          % running[2].strip())
    check(ok and stop == 0 and kp == 0 and saved[0] == 0 and "13 parameters saved" in saved[1]
          and "save: the link's 13 parameters saved" in live.err,
          "stop, set speed_kp_Nms_rad=%g, save, quit: drivetool and drive_sil say the 13 were saved" % KP)

    live = Live(drive_sil, drivetool, scen, nv, tmp)
    rc, out, _ = live.tool("--json", "get", "speed_kp_Nms_rad", "nv_status")
    got = json.loads(out) if rc == 0 else {}
    ok = live.quit()
    want = struct.unpack("<f", struct.pack("<f", KP))[0]
    check(ok and "loaded 13 parameters" in live.err and "speed_kp_Nms_rad=%.9g" % want in live.err
          and got.get("speed_kp_Nms_rad") == want and got.get("nv_status") == VALID,
          "a new run with --nv FILE: stderr names the 13 loaded, get reads speed_kp %g back, nv_status VALID"
          % KP)
    return nv


def main():
    drive_sil, drivetool = sys.argv[1], sys.argv[2]
    keys = link_keys()
    table = table_id(keys)
    tmp = tempfile.mkdtemp()
    try:
        scen = os.path.join(tmp, "m.ini")
        with open(scen, "w") as f:
            f.write("[controller]\nmode = torque\n")
        live_scen = os.path.join(tmp, "live.ini")
        with open(live_scen, "w") as f:
            f.write("[controller]\nmode = speed\n[run]\nduration_s = 0\n")
        nv = os.path.join(tmp, "nv.bin")
        out = os.path.join(tmp, "run.csv")

        r, res = run(drive_sil, scen, nv, out)
        with open(nv, "rb") as f:
            erased = f.read()
        check(r.returncode == 0 and "NV_EMPTY" in r.stderr and erased == b"\xff" * (2 * WORDS),
              "no FILE: NV_EMPTY on stderr, FILE written as an erased 32K-word sector")
        kp_default = res["controller.speed_kp_Nms_rad"]["value"]

        saved = round_trip(drive_sil, drivetool, tmp, live_scen)
        with open(saved, "rb") as f:
            good = bytearray(f.read())
        at = 2 * (HEADER + PAIR * keys.index("speed_kp_Nms_rad") + 1)   # kp's value, low word, low octet
        good[at] ^= 0x01
        write(nv, bytes(good))
        r, res = run(drive_sil, scen, nv, out)
        check(r.returncode == 0 and "NV_INVALID" in r.stderr and res["controller.speed_kp_Nms_rad"]["value"] ==
              kp_default and "final state 5 (RUN)" in r.stdout,
              "one byte of the saved block corrupted: NV_INVALID on stderr, the run on its speed_kp %g" % kp_default)

        blk = block([("speed_kp_Nms_rad", 0.321), ("J_kgm2", 0.0021)], table)
        write(nv, image(blk))
        r, res = run(drive_sil, scen, nv, out)
        kp, J = res["controller.speed_kp_Nms_rad"], res["controller.J_kgm2"]
        check(r.returncode == 0 and "loaded 2 parameters" in r.stderr and "speed_kp_Nms_rad=0.321" in r.stderr
              and abs(kp["value"] - 0.321) < 1e-7 and kp["source"] == "set" and abs(J["value"] - 0.0021) < 1e-9,
              "a block built here: both values taken (stderr: %s)" % r.stderr.strip().splitlines()[0])

        for at in (2 * HEADER + 1, 2 * HEADER + 3, 2 * (len(blk) - 1)):   # the first id's high octet, its value's, the CRC's
            bad = bytearray(image(blk))
            bad[at] ^= 0x20
            write(nv, bytes(bad))
            r, res = run(drive_sil, scen, nv, out)
            check(r.returncode == 0 and "NV_INVALID" in r.stderr and
                  res["controller.speed_kp_Nms_rad"]["value"] == kp_default,
                  "byte %d of the block corrupted: NV_INVALID, the scenario's speed_kp %g" % (at, kp_default))

        write(nv, image(block([("speed_kp_Nms_rad", 0.321)], table_id(keys[:-1]))))
        r, res = run(drive_sil, scen, nv, out)
        check(r.returncode == 0 and "NV_INVALID" in r.stderr and "table" in r.stderr and
              res["controller.speed_kp_Nms_rad"]["value"] == kp_default,
              "a block of the table without its last key (an older image's): NV_INVALID, the scenario's values")

        write(nv, image(block([("no_such_key", 1.0)], table)))
        r, _ = run(drive_sil, scen, nv, out)
        check(r.returncode == 0 and "NV_INVALID" in r.stderr and "0x%04X" % key_id("no_such_key") in r.stderr,
              "a block naming no parameter of the link's table: NV_INVALID naming its id")

        write(nv, image(block([("R_ohm", 5000.0)], table)))
        r, res = run(drive_sil, scen, nv, out)
        check(r.returncode == 0 and "NV_INVALID" in r.stderr and "R_ohm" in r.stderr and
              res["controller.R_ohm"]["value"] == 3,
              "a saved R_ohm beyond its plausibility bound: NV_INVALID naming it, R 3 ohm")

        write(nv, b"\xff" * 100)
        r, _ = run(drive_sil, scen, nv, out)
        check(r.returncode == 2 and "not a parameter sector" in r.stderr, "a FILE of 100 bytes: exit 2")

        live = Live(drive_sil, drivetool, live_scen, None, tmp)
        live.tool("stop")
        rc, _, err = live.tool("save")
        status = live.tool("--json", "get", "nv_status")[1]
        ok = live.quit()
        check(ok and rc == 1 and "no parameter store" in err and json.loads(status)["nv_status"] == 0,
              "a link run without --nv: save refused (no parameter store), nv_status NONE")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
    sys.exit(check.close())

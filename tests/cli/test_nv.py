#!/usr/bin/env python3
"""test_nv.py DRIVE_SIL - drive_sil --nv FILE (tools/sil/nv_file.h): the
parameter sector kept in FILE, read before the run as the board reads its
flash at start-up (firmware/params/nv_store.h).

The sector images here are built by this test from nv_store.h's format,
with its own CRC32_PRIME and key-id hash (independent of the firmware's
code): a block saying speed_kp_Nms_rad = 0.321 and J_kgm2 = 0.0021 is
loaded (stderr names both, .resolved.json has them, source "set"); one
byte of it corrupted: NV_INVALID on stderr and the scenario's own values;
no FILE: NV_EMPTY and FILE written as an erased sector; a FILE of the
wrong size: exit 2. Standard library only.
"""
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile

from checks import Checks

WORDS = 0x8000
MAGIC, VERSION = 0x4E56, 1

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


def key_id(name):
    c = crc32_prime(name.encode())
    return (c >> 16) ^ (c & 0xFFFF)


def block(pairs):
    w = [MAGIC, VERSION, 5 + 3 * len(pairs)]
    for name, v in pairs:
        u = struct.unpack("<I", struct.pack("<f", v))[0]
        w += [key_id(name), u & 0xFFFF, u >> 16]
    c = crc32_prime(words_octets(w))
    return w + [c & 0xFFFF, c >> 16]


def image(words):
    w = words + [0xFFFF] * (WORDS - len(words))
    return bytes(words_octets(w))


def run(drive_sil, scen, nv, out):
    r = subprocess.run([drive_sil, "--scenario", scen, "--set", "run.duration_s=0.002", "--nv", nv, "--out", out],
                       capture_output=True, text=True)
    res = None
    if os.path.exists(out[:-4] + ".resolved.json"):
        res = json.load(open(out[:-4] + ".resolved.json"))["keys"]
    return r, res


def main():
    drive_sil = sys.argv[1]
    tmp = tempfile.mkdtemp()
    try:
        scen = os.path.join(tmp, "m.ini")
        with open(scen, "w") as f:
            f.write("[controller]\nmode = torque\n")
        nv = os.path.join(tmp, "nv.bin")
        out = os.path.join(tmp, "run.csv")

        r, res = run(drive_sil, scen, nv, out)
        erased = open(nv, "rb").read() if os.path.exists(nv) else b""
        check(r.returncode == 0 and "NV_EMPTY" in r.stderr and erased == b"\xff" * (2 * WORDS),
              "no FILE: NV_EMPTY on stderr, FILE written as an erased 32K-word sector")
        kp_default = res["controller.speed_kp_Nms_rad"]["value"]

        blk = block([("speed_kp_Nms_rad", 0.321), ("J_kgm2", 0.0021)])
        with open(nv, "wb") as f:
            f.write(image(blk))
        r, res = run(drive_sil, scen, nv, out)
        kp, J = res["controller.speed_kp_Nms_rad"], res["controller.J_kgm2"]
        check(r.returncode == 0 and "loaded 2 parameters" in r.stderr and "speed_kp_Nms_rad=0.321" in r.stderr
              and abs(kp["value"] - 0.321) < 1e-7 and kp["source"] == "set" and abs(J["value"] - 0.0021) < 1e-9,
              "a saved block: both values taken (stderr: %s)" % r.stderr.strip().splitlines()[0])

        for at in (7, 9, 2 * (len(blk) - 1)):   # the first id's high octet, its value's, the CRC's
            bad = bytearray(image(blk))
            bad[at] ^= 0x20
            with open(nv, "wb") as f:
                f.write(bytes(bad))
            r, res = run(drive_sil, scen, nv, out)
            check(r.returncode == 0 and "NV_INVALID" in r.stderr and
                  res["controller.speed_kp_Nms_rad"]["value"] == kp_default,
                  "byte %d of the block corrupted: NV_INVALID, the scenario's speed_kp %g" % (at, kp_default))

        with open(nv, "wb") as f:
            f.write(image(block([("no_such_key", 1.0)])))
        r, _ = run(drive_sil, scen, nv, out)
        check(r.returncode == 0 and "NV_INVALID" in r.stderr and "0x%04X" % key_id("no_such_key") in r.stderr,
              "a block naming no [controller] key: NV_INVALID naming its id")

        with open(nv, "wb") as f:
            f.write(image(block([("R_ohm", 5000.0)])))
        r, res = run(drive_sil, scen, nv, out)
        check(r.returncode == 0 and "NV_INVALID" in r.stderr and "R_ohm" in r.stderr and
              res["controller.R_ohm"]["value"] == 3,
              "a saved R_ohm beyond its plausibility bound: NV_INVALID naming it, R 3 ohm")

        with open(nv, "wb") as f:
            f.write(b"\xff" * 100)
        r, _ = run(drive_sil, scen, nv, out)
        check(r.returncode == 2 and "not a parameter sector" in r.stderr, "a FILE of 100 bytes: exit 2")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
    sys.exit(check.close())

#!/usr/bin/env python3
"""test_nv.py DRIVE_SIL - drive_sil --nv FILE (tools/sil/nv_file.h): the
parameter sector kept in FILE, read before the run as the board reads its
flash at start-up (firmware/params/nv_store.h), a block of the link's
parameter table only (firmware/link/link_nv.h).

The sector images are built here from nv_store.h's words, with this
file's own CRC32_PRIME, key ids and table id (the link table's keys read
from firmware/link/link_params.h), independent of the firmware's code: a block of two of the table's parameters is loaded; a
block of another table (the table without its last key), of a key not in
it, or of a value beyond its bound is NV_INVALID naming why where it can;
a FILE of the wrong size exits 2. Standard library only.
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


def main():
    drive_sil = sys.argv[1]
    keys = link_keys()
    table = table_id(keys)
    tmp = tempfile.mkdtemp()
    try:
        scen = os.path.join(tmp, "m.ini")
        with open(scen, "w") as f:
            f.write("[controller]\nmode = torque\n")
        nv = os.path.join(tmp, "nv.bin")
        out = os.path.join(tmp, "run.csv")

        r, res = run(drive_sil, scen, nv, out)
        with open(nv, "rb") as f:
            erased = f.read()
        check(r.returncode == 0 and "NV_EMPTY" in r.stderr and erased == b"\xff" * (2 * WORDS),
              "no FILE: NV_EMPTY on stderr, FILE written as an erased 32K-word sector")
        kp_default = res["controller.speed_kp_Nms_rad"]["value"]

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

    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
    sys.exit(check.close())

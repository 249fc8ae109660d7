#!/usr/bin/env python3
"""test_board.py DRIVE_SIL - `make board MOTOR=FILE.ini` (tools/sil/board_config.h).

On a motor file unlike the paper's (a 48 V five-pole-pair motor whose
controller is told commissioned values that differ from its plant's):
- the JSON's R, L, psi_f, pole pairs, J, encoder offset, i_rated and i_peak
  are the file's, to the digit;
- every value the JSON shares with drive_sil's OUT.resolved.json of a run
  of the same file is the run's (the keys a run defaults to a
  simulation's, the start level among them, excepted: the file leaves
  only [run] level unset, and the image's level is 1 where the run's is 5);
- what the compiled image holds (tests/board_values.c on make board's
  objects) is the JSON's;
- [controller] psif_Wb = 50 makes make board exit 2 naming the key, with
  no configuration written; without MOTOR the image is the paper
  motor's at level 1; make firmware MOTOR=... without TI's tools stops
  naming CG_TOOL_ROOT.
Standard library only.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from checks import Checks

MOTOR = """; a 48 V five-pole-pair servo motor; [controller] as --commission measured it
[plant]
R_ohm = 0.125
L_H = 0.00036
psif_Wb = 0.0205
pole_pairs = 5
J_kgm2 = 0.000125
vdc_V = 48
deadtime_s = 5e-07
encoder_lines = 1024
adc_full_scale_A = 30
trip_A = 32
[motor]
i_rated_A = 8.2
i_peak_A = 20
n_rated_rpm = 2500
[controller]
R_ohm = 0.12
L_H = 0.00035
psif_Wb = 0.02
pole_pairs = 5
J_kgm2 = 0.00012
encoder_offset_el_rad = 1.234
speed_kp_Nms_rad = 0.05
[run]
calibrate = on
align = off
"""
# the file's told values, as the Done-when lists them
FILE_VALUES = {("controller", "R_ohm"): 0.12, ("controller", "L_H"): 0.00035, ("controller", "psif_Wb"): 0.02,
               ("controller", "pole_pairs"): 5, ("controller", "J_kgm2"): 0.00012,
               ("controller", "encoder_offset_el_rad"): 1.234, ("motor", "i_rated_A"): 8.2,
               ("motor", "i_peak_A"): 20, ("board", "deadtime_s"): 5e-07, ("board", "encoder_lines"): 1024,
               ("board", "adc_full_scale_A"): 30, ("board", "trip_A"): 32, ("board", "vdc_V"): 48,
               ("controller", "speed_kp_Nms_rad"): 0.05}
# a float of the image against the double it was told: the float's rounding
FLOAT_REL = 1e-6

check = Checks("test_board")


def close(a, b, rel):
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-30)


BUILD = None   # the build drive_sil comes from (BUILD/host/drive_sil, as make spells it): make board uses the same


def make(*args):
    # not the caller's flags, jobserver or variables: one make of our own, on the caller's build
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS", "MAKEOVERRIDES")}
    return subprocess.run(["make", "--no-print-directory", "BUILD=" + BUILD] + list(args), capture_output=True,
                          text=True, env=env)


def main():
    global BUILD
    drive_sil = sys.argv[1]
    # spelled as the caller's make spells it (relative to the repository): another spelling names
    # other targets, and that make would link drive_sil again under the suites running it
    BUILD = os.path.dirname(os.path.dirname(drive_sil)) or "."
    tmp = tempfile.mkdtemp()
    try:
        motor = os.path.join(tmp, "servo48.ini")
        with open(motor, "w") as f:
            f.write(MOTOR)
        out = os.path.join(tmp, "board")
        values = os.path.join(out, "board_values")
        r = make("board", "MOTOR=" + motor, "BOARD_OUT=" + out, values)
        check(r.returncode == 0, "make board MOTOR=servo48.ini exits 0 (%s)" % (r.stderr.strip()[-300:] or "ok"))
        if r.returncode != 0:
            return
        js = json.load(open(os.path.join(out, "drive_config.json")))
        check(sorted(js) == ["board", "controller", "drive_sil", "identify", "motor", "overrides", "run", "scenario"],
              "drive_config.json's groups: controller, motor, identify, run, board (no plant)")
        bad = ["%s.%s = %r, the file's %r" % (g, k, js[g][k], v) for (g, k), v in FILE_VALUES.items()
               if js[g][k] != v]
        check(not bad, "the JSON's R, L, psi_f, pole pairs, J, encoder offset, i_rated, i_peak, "
              "speed_kp and board facts are the file's" + ("" if not bad else ": " + "; ".join(bad)))
        check(js["run"]["level"] == 1, "the image's build level is 1 (the file sets none)")

        # the same file run by drive_sil: its resolved keys
        csv = os.path.join(tmp, "run.csv")
        r = subprocess.run([drive_sil, "--scenario", motor, "--set", "run.duration_s=0.001", "--out", csv],
                           capture_output=True, text=True)
        res = json.load(open(os.path.join(tmp, "run.resolved.json")))["keys"]
        differ, compared = [], 0
        for g, keys in js.items():
            if not isinstance(keys, dict):
                continue
            section = "plant" if g == "board" else g
            for k, v in keys.items():
                rv = res["%s.%s" % (section, k)]["value"]
                if rv is None or (section, k) == ("run", "level"):
                    continue   # left to the drive in a run (derived at its start); the bench's level
                compared += 1
                if not close(v, rv, 1e-9):
                    differ.append("%s.%s %r != %r" % (g, k, v, rv))
        check(not differ and compared >= 40, "%d values equal drive_sil's resolved ones for the same file%s"
              % (compared, "" if not differ else ": " + "; ".join(differ)))
        check(res["run.level"]["value"] == 5, "drive_sil's own run of it stays at level 5")

        # the compiled image: what board_values reads from make board's objects
        r = subprocess.run([values], capture_output=True, text=True)
        img = json.loads(r.stdout)
        differ = ["%s.%s image %r, JSON %r" % (g, k, v, js[g][k]) for g, keys in img.items()
                  for k, v in keys.items() if not close(v, js[g][k], FLOAT_REL)]
        check(r.returncode == 0 and not differ, "the compiled image holds the JSON's %d values%s"
              % (sum(len(x) for x in img.values()), "" if not differ else ": " + "; ".join(differ)))

        # an absurd flux: exit 2, the key named, nothing written
        badm = os.path.join(tmp, "bad.ini")
        with open(badm, "w") as f:
            f.write(MOTOR.replace("psif_Wb = 0.02\n", "psif_Wb = 50\n"))
        bout = os.path.join(tmp, "bad_board")
        r = make("board", "MOTOR=" + badm, "BOARD_OUT=" + bout)
        named = "[controller] psif_Wb" in r.stdout + r.stderr
        check(r.returncode != 0 and driver_exit(drive_sil, badm) == 2 and named
              and not os.path.exists(os.path.join(bout, "drive_config.h")),
              "psif_Wb = 50: make board fails, drive_sil exits 2 naming [controller] psif_Wb, no header")

        # no motor file: the board's own defaults, the paper motor at level 1
        dout = os.path.join(tmp, "default_board")
        r = make(os.path.join(dout, "board_values"), "BOARD_OUT=" + dout)
        d = json.loads(subprocess.run([os.path.join(dout, "board_values")], capture_output=True, text=True).stdout) \
            if r.returncode == 0 else {}
        check(r.returncode == 0 and d["controller"]["R_ohm"] == 3 and d["run"]["level"] == 1
              and close(d["board"]["deadtime_s"], 1e-6, 1e-12),
              "without MOTOR: the paper motor (R 3 ohm), level 1, 1 us dead time")

        # make firmware without TI's tools: the clear stop, before anything is built
        env_keep = {k: os.environ.pop(k) for k in ("CG_TOOL_ROOT", "C2000WARE_ROOT") if k in os.environ}
        r = make("firmware", "MOTOR=" + motor, "BOARD_OUT=" + out)
        os.environ.update(env_keep)
        check(r.returncode != 0 and "CG_TOOL_ROOT" in r.stdout + r.stderr,
              "make firmware MOTOR=... without TI's tools stops naming CG_TOOL_ROOT")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def driver_exit(drive_sil, motor):
    d = tempfile.mkdtemp()
    try:
        return subprocess.run([drive_sil, "--scenario", motor, "--board-config", d], capture_output=True).returncode
    finally:
        shutil.rmtree(d, ignore_errors=True)


if __name__ == "__main__":
    main()
    sys.exit(check.close())

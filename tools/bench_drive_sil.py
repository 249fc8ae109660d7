#!/usr/bin/env python3
"""bench_drive_sil.py DRIVE_SIL - `make bench`: drive_sil as a whole process
(start-up, scenario parsing, the run, the CSV with log_every = 10) on the
paper's 1.2 s scenarios, both inverter models, best of REPEATS wall-clock
runs, printed as multiples of real time. Prints, never asserts; the
machine's load moves the figures (callgrind's instruction counts are the
stable measure: valgrind --tool=callgrind DRIVE_SIL --scenario ...)."""
import os
import resource
import subprocess
import sys
import tempfile
import time

REPEATS = 10
SCENARIOS = ("tools/scenarios/prop_paper.ini", "tools/scenarios/conv_paper.ini")
MODELS = ("switching", "averaged")
DURATION_S = 1.2


def children_cpu_s():
    """CPU seconds (user + system) of the finished child processes (clock-tick resolution)."""
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def main(argv):
    exe = argv[1] if len(argv) > 1 else os.path.join("build", "host", "drive_sil")
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "run.csv")
        for sc in SCENARIOS:
            for m in MODELS:
                cmd = [exe, "--scenario", sc, "--set", f"plant.model={m}", "--set", "run.log_every=10",
                       "--out", out]
                best = float("inf")
                cpu0 = children_cpu_s()
                for _ in range(REPEATS):
                    t0 = time.perf_counter()
                    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
                    best = min(best, time.perf_counter() - t0)
                cpu = (children_cpu_s() - cpu0) / REPEATS
                print(f"bench drive_sil {os.path.basename(sc):16s} {m:9s} whole process {best * 1e3:6.2f} ms: "
                      f"{DURATION_S / best:5.0f} x real time (best of {REPEATS}; mean CPU {cpu * 1e3:.1f} ms, "
                      f"{DURATION_S / cpu:.0f} x)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

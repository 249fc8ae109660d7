#!/usr/bin/env python3
"""bench_drive_sil.py DRIVE_SIL - `make bench`: drive_sil as a whole process
(process start, scenario parsing, the run, the CSV with log_every = 10 and
its .resolved.json, each written to a temporary name and renamed) on the
paper's 1.2 s scenarios, both inverter models, best of REPEATS wall-clock
runs, printed as multiples of real time. drive_sil formats and writes the
CSV on a second thread (tools/sil/csv_writer.h), so the figure depends on
a free second core. Beside it, the same run with no CSV at all (--summary
only): the start-up and the simulation alone. Prints, never asserts; the
machine's load moves the figures (callgrind's instruction counts are the
stable measure: valgrind --tool=callgrind --separate-threads=yes DRIVE_SIL
--scenario ...)."""
import os
import resource
import subprocess
import sys
import tempfile
import time

REPEATS = 10
EXIT_FAULT = 3   # drive_sil: the run ended in FAULT, its outputs complete - a result
SCENARIOS = ("tools/scenarios/prop_paper.ini", "tools/scenarios/conv_paper.ini")
MODELS = ("switching", "averaged")
DURATION_S = 1.2


def children_cpu_s():
    """CPU seconds (user + system) of the finished child processes (clock-tick resolution)."""
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def best_wall_s(cmd):
    """Best wall time of REPEATS runs of cmd, and its mean CPU time (all threads)."""
    best = float("inf")
    cpu0 = children_cpu_s()
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        rc = subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode
        if rc not in (0, EXIT_FAULT):
            raise subprocess.CalledProcessError(rc, cmd)
        best = min(best, time.perf_counter() - t0)
    return best, (children_cpu_s() - cpu0) / REPEATS


def main(argv):
    exe = argv[1] if len(argv) > 1 else os.path.join("build", "host", "drive_sil")
    with tempfile.TemporaryDirectory() as d:
        for sc in SCENARIOS:
            for m in MODELS:
                run = [exe, "--scenario", sc, "--set", f"plant.model={m}", "--set", "run.log_every=10"]
                best, cpu = best_wall_s(run + ["--out", os.path.join(d, "run.csv")])
                bare, _ = best_wall_s(run + ["--summary", os.path.join(d, "run.json")])
                print(f"bench drive_sil {os.path.basename(sc):16s} {m:9s} whole process {best * 1e3:6.2f} ms: "
                      f"{DURATION_S / best:5.0f} x real time (best of {REPEATS}; mean CPU {cpu * 1e3:.1f} ms, "
                      f"{DURATION_S / cpu:.0f} x; no CSV {bare * 1e3:.2f} ms, {DURATION_S / bare:.0f} x)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

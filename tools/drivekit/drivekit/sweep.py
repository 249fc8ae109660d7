#!/usr/bin/env python3
"""sweep.py - runs a scenario over a grid of parameters for each control
method through drive_sil and writes one row per point and method.

  sweep.py --scenario FILE [--set section.key=value ...]
           --grid NAME=START:STOP:N [--grid ...] [--log]
           [--methods conventional,proposed] [--jobs N] --out DIR

NAME is a scenario key (section.key, as drive_sil --help lists them), or a
template name without a dot that --set values use as {NAME}, e.g.
  --grid load_Nm=0.5:6:6 --set "load.torque_Nm=0:2, 0.35:4, 0.6:{load_Nm}"
START:STOP:N is N evenly spaced values from START to STOP (N = 1: START);
--log spaces every grid logarithmically, a grid's own ":log" or ":lin"
suffix overrides it.

The method is set per run (controller.method; the conventional method
also gets identify.mode=off: it has no step 1, as conv_*.ini). Every
point x method runs in one of --jobs drive_sil --batch workers (one
process per core, fed through its stdin; the runs' figures are computed in
C over the scenario's steady window, tools/sil/summary.h, the same as
drivekit.metrics'). DIR/results.csv gets a row as each point finishes:
the method, the grid values, the resolved plant and controller parameters,
the final state and fault, peak |i| and the figures, columns named with
their units (sweep.RESULT_COLS). An interrupted sweep resumes: points
already in results.csv are skipped, unless DIR/sweep.json shows another
scenario, other overrides or another drive_sil build (then it starts
afresh). Only whole rows ending in a newline are trusted; the file is
rewritten sorted at the end (through a temporary and a rename).

A bad key, range, method or scenario is found before anything runs (the
grid's corners go through drive_sil --check): exit 2 with a message naming
it, nothing written. A point whose run fails exits 1 at the end. The
progress bar (rate, time left) is tqdm's when installed (the venv of
make sweep), else a plain line on stderr.
"""
import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import queue
import re
import subprocess
import sys
import threading
import time

EXIT_BAD_INPUT = 2
METHODS = ("conventional", "proposed")
# A method's overrides, applied last: the conventional method has no step 1
# (as tools/scenarios/conv_*.ini), whatever the scenario's [identify] says.
METHOD_SETS = {"conventional": ["controller.method=conventional", "identify.mode=off"],
               "proposed": ["controller.method=proposed"]}
DEFAULT_DRIVE_SIL = os.path.join("build", "host", "drive_sil")
RESULTS = "results.csv"
DEFINITION = "sweep.json"
TEMPLATE = re.compile(r"\{([A-Za-z_][A-Za-z0-9_]*)\}")
# Figures and run results from drive_sil's summary, in results.csv's order.
RESULT_COLS = ("plant.R_ohm", "plant.L_H", "plant.psif_Wb",
               "controller.R_ohm", "controller.L_H", "controller.psif_Wb",
               "final_state_name", "fault_name", "warning", "max_abs_i_A", "t_run_s",
               "te_err_Nm", "te_ripple_Nm", "psi_err_Wb", "psi_err_pct",
               "speed_err_rpm", "speed_err_max_rpm", "id_A", "iq_A",
               "R_err_pct", "L_err_pct", "psif_err_pct", "window_t0_s", "window_t1_s")
STATUS_OK = "ok"


class BadInput(Exception):
    """A problem with the command line: exit 2, nothing written."""


class Grid:
    """One --grid: NAME=START:STOP:N[:log|:lin]."""

    def __init__(self, text, log_default):
        name, eq, spec = text.partition("=")
        if not eq or not name:
            raise BadInput(f"--grid {text}: expected NAME=START:STOP:N")
        parts = spec.split(":")
        log = log_default
        if len(parts) == 4 and parts[3] in ("log", "lin"):
            log = parts.pop() == "log"
        if len(parts) != 3:
            raise BadInput(f"--grid {text}: expected NAME=START:STOP:N[:log|:lin]")
        try:
            start, stop = float(parts[0]), float(parts[1])
        except ValueError:
            raise BadInput(f"--grid {text}: START and STOP must be numbers") from None
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise BadInput(f"--grid {text}: START and STOP must be finite")
        if not re.fullmatch(r"[0-9]+", parts[2]) or int(parts[2]) < 1:
            raise BadInput(f"--grid {text}: N must be a whole number >= 1 (got {parts[2]!r})")
        n = int(parts[2])
        if n == 1 and start != stop:
            raise BadInput(f"--grid {text}: N = 1 needs START = STOP")
        if log and not (start > 0 and stop > 0):
            raise BadInput(f"--grid {text}: a logarithmic grid needs START and STOP > 0")
        self.text, self.name, self.start, self.stop, self.n, self.log = text, name, start, stop, n, log
        self.is_key = "." in name
        if not self.is_key and not re.fullmatch(TEMPLATE.pattern[2:-2], name):
            raise BadInput(f"--grid {text}: NAME must be section.key or a template name (letters, digits, _)")

    def values(self):
        if self.n == 1:
            return [self.start]
        if self.log:
            a, b = math.log(self.start), math.log(self.stop)
            return [math.exp(a + (b - a) * k / (self.n - 1)) for k in range(self.n)]
        return [self.start + (self.stop - self.start) * k / (self.n - 1) for k in range(self.n)]


def fmt_value(v):
    """A grid value as written to drive_sil and results.csv (round-trips exactly)."""
    return repr(float(v))


def point_sets(sets, grids, values, method):
    """The overrides of one point: --set values with templates filled, the grid keys, the method."""
    env = {g.name: fmt_value(v) for g, v in zip(grids, values)}
    out = [TEMPLATE.sub(lambda m: env[m.group(1)], s) for s in sets]
    out += [f"{g.name}={env[g.name]}" for g in grids if g.is_key]
    out += METHOD_SETS[method]
    return out


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenario", required=True)
    ap.add_argument("--set", action="append", default=[], metavar="section.key=value")
    ap.add_argument("--grid", action="append", default=[], metavar="NAME=START:STOP:N")
    ap.add_argument("--log", action="store_true", help="logarithmic spacing for every grid")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", required=True, metavar="DIR")
    ap.add_argument("--window", default=None, metavar="T0:T1", help="steady window [s] (drive_sil's default)")
    ap.add_argument("--drive-sil", default=DEFAULT_DRIVE_SIL)
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    return ap.parse_args(argv)


def check_definition(a):
    """Grids, methods, templates and jobs from the arguments; BadInput naming the problem."""
    if not a.grid:
        raise BadInput("at least one --grid is needed")
    grids = [Grid(t, a.log) for t in a.grid]
    names = [g.name for g in grids]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise BadInput(f"--grid {dup[0]} given twice")
    methods = [m.strip() for m in a.methods.split(",") if m.strip()]
    bad = [m for m in methods if m not in METHODS]
    if not methods or bad:
        raise BadInput(f"--methods {a.methods}: expected a list of {', '.join(METHODS)}")
    if len(set(methods)) != len(methods):
        raise BadInput(f"--methods {a.methods}: a method given twice")
    if a.jobs < 1:
        raise BadInput(f"--jobs {a.jobs}: must be >= 1")
    for s in a.set:
        key = s.partition("=")[0].strip()
        if key == "controller.method":
            raise BadInput(f"--set {s}: the method comes from --methods")
        if key in names:
            raise BadInput(f"--set {s}: {key} is swept by --grid")
        for t in TEMPLATE.findall(s):
            if t not in names or next(g for g in grids if g.name == t).is_key:
                raise BadInput(f"--set {s}: {{{t}}} is not a template --grid")
    used = {t for s in a.set for t in TEMPLATE.findall(s)}
    for g in grids:
        if not g.is_key and g.name not in used:
            raise BadInput(f"--grid {g.text}: template {g.name} is used by no --set as {{{g.name}}}")
    if not os.path.isfile(a.scenario):
        raise BadInput(f"--scenario {a.scenario}: no such file")
    if not (os.path.isfile(a.drive_sil) and os.access(a.drive_sil, os.X_OK)):
        raise BadInput(f"--drive-sil {a.drive_sil}: not an executable (make build/host/drive_sil)")
    return grids, methods


def check_with_drive_sil(a, grids, methods):
    """Every corner of the grid through drive_sil --check: keys, values and ranges as it takes them."""
    corners = itertools.product(*[sorted({g.values()[0], g.values()[-1]}) for g in grids])
    for values in corners:
        for m in methods:
            cmd = [a.drive_sil, "--scenario", a.scenario, "--check"]
            if a.window:
                cmd += ["--window", a.window]
            for s in point_sets(a.set, grids, values, m):
                cmd += ["--set", s]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                msg = (r.stderr.strip().splitlines() or [f"exit {r.returncode}"])[0]
                at = ", ".join(f"{g.name}={fmt_value(v)}" for g, v in zip(grids, values))
                culprit = next((f"--grid {g.text}" for g in grids
                                if g.is_key and "[{}] {}:".format(*g.name.split(".", 1)) in msg), None)
                raise BadInput(f"{culprit or '--scenario/--set'} (at {at}, {m}): {msg}")


def file_sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 16), b""):
            h.update(chunk)
    return h.hexdigest()


def definition_of(a, grids):
    """What results.csv's rows depend on besides their grid values and method."""
    return {"scenario": os.path.abspath(a.scenario), "scenario_sha256": file_sha256(a.scenario),
            "set": a.set, "method_sets": METHOD_SETS, "grid_names": [g.name for g in grids], "window": a.window,
            "drive_sil_sha256": file_sha256(a.drive_sil)}


def columns(grids):
    return ["method"] + [g.name for g in grids] + list(RESULT_COLS) + ["status"]


def point_key(method, values):
    return (method,) + tuple(fmt_value(v) for v in values)


def load_done(out_dir, definition, cols):
    """{point key: row} of the trusted rows of out_dir/results.csv: the same definition, the same
    columns, whole lines, status ok. Anything else is dropped (and said)."""
    path = os.path.join(out_dir, RESULTS)
    if not os.path.exists(path):
        return {}
    try:
        with open(os.path.join(out_dir, DEFINITION)) as f:
            old = json.load(f)
    except (OSError, ValueError):
        old = None
    if old != definition:
        print(f"sweep.py: {path}: written for another scenario, overrides or drive_sil build: starting afresh",
              file=sys.stderr)
        return {}
    with open(path, newline="") as f:
        text = f.read()
    lines = text.split("\n")
    complete = lines[:-1]             # the part after the last newline is unfinished
    rows = list(csv.reader(complete))
    if not rows or rows[0] != cols:
        print(f"sweep.py: {path}: other columns: starting afresh", file=sys.stderr)
        return {}
    done = {}
    ng = len(cols) - len(RESULT_COLS) - 2
    for r in rows[1:]:
        if len(r) != len(cols) or r[-1] != STATUS_OK:
            continue
        try:
            key = point_key(r[0], [float(x) for x in r[1:1 + ng]])
        except ValueError:
            continue
        done[key] = r
    return done


class Workers:
    """--jobs drive_sil --batch processes; run() hands out points and yields (key, summary dict).
    A point that ends in FAULT is answered with its summary like any other: --batch exits 0
    whatever its points did (a single run's exit 3, FAULT, is a result too, not an error)."""

    def __init__(self, a, jobs):
        self.cmd = [a.drive_sil, "--scenario", a.scenario, "--batch"]
        if a.window:
            self.cmd += ["--window", a.window]
        self.jobs = jobs

    def run(self, points):
        todo = queue.Queue()
        for p in points:
            todo.put(p)
        results = queue.Queue()

        def worker():
            proc = subprocess.Popen(self.cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, text=True, bufsize=1)
            try:
                while True:
                    try:
                        key, sets = todo.get_nowait()
                    except queue.Empty:
                        break
                    proc.stdin.write("\t".join([str(id(key))] + sets) + "\n")
                    proc.stdin.flush()
                    line = proc.stdout.readline()
                    if not line:
                        err = proc.stderr.read().strip() if proc.poll() is not None else ""
                        results.put((key, {"error": f"drive_sil ended: exit {proc.wait()} {err}".strip()}))
                        proc = subprocess.Popen(self.cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                                stderr=subprocess.PIPE, text=True, bufsize=1)
                        continue
                    try:
                        results.put((key, json.loads(line)))
                    except ValueError:
                        results.put((key, {"error": f"drive_sil: not a summary: {line.strip()[:200]}"}))
            finally:
                proc.stdin.close()
                proc.wait()
            results.put(None)

        threads = [threading.Thread(target=worker, daemon=True) for _ in range(self.jobs)]
        for t in threads:
            t.start()
        running = len(threads)
        while running:
            item = results.get()
            if item is None:
                running -= 1
            else:
                yield item


class Progress:
    """tqdm when installed, else a line on stderr now and then: done/total, rate, time left."""

    def __init__(self, total, quiet):
        self.total, self.quiet, self.n, self.t0, self.last = total, quiet, 0, time.monotonic(), 0.0
        self.bar = None
        if not quiet:
            try:
                from tqdm import tqdm
                self.bar = tqdm(total=total, unit="pt", smoothing=0.1)
            except ImportError:
                pass

    def update(self):
        self.n += 1
        if self.bar is not None:
            self.bar.update(1)
            return
        now = time.monotonic()
        if self.quiet or (now - self.last < 1.0 and self.n < self.total):
            return
        self.last = now
        rate = self.n / max(now - self.t0, 1e-9)
        left = (self.total - self.n) / rate if rate > 0 else math.nan
        print(f"\rsweep: {self.n}/{self.total} points, {rate:.0f} pt/s, {left:.0f} s left",
              end="\n" if self.n >= self.total else "", file=sys.stderr, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def children_cpu_s():
    """CPU seconds (user + system) of the finished drive_sil workers: a figure the machine's load
    moves far less than the wall time."""
    try:
        import resource
    except ImportError:
        return math.nan
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def csv_cell(v):
    if v is None:
        return "nan"
    if v == "":
        return "-"             # no warning: a visible cell, not an empty field
    if isinstance(v, float):
        return repr(v)
    return str(v)


def row_of(method, values, summary):
    if "error" in summary:
        figures = ["nan"] * len(RESULT_COLS)
        figures[RESULT_COLS.index("fault_name")] = "ERROR"
        return [method] + [fmt_value(v) for v in values] + figures + ["error: " + summary["error"]]
    return ([method] + [fmt_value(v) for v in values] + [csv_cell(summary.get(c)) for c in RESULT_COLS]
            + [STATUS_OK])


def line_of(row):
    """One CSV line (csv's quoting), written with one os.write so a row is whole or absent."""
    import io
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(row)
    return buf.getvalue()


def write_sorted(path, cols, rows):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(cols)
        w.writerows(rows)
    os.replace(tmp, path)


def sweep(a):
    grids, methods = check_definition(a)
    check_with_drive_sil(a, grids, methods)
    definition = definition_of(a, grids)
    cols = columns(grids)
    os.makedirs(a.out, exist_ok=True)
    done = load_done(a.out, definition, cols)
    path = os.path.join(a.out, RESULTS)
    # start results.csv afresh with the trusted rows, the definition beside it
    write_sorted(path, cols, list(done.values()))
    tmp = os.path.join(a.out, DEFINITION + f".tmp.{os.getpid()}")
    with open(tmp, "w") as f:
        json.dump(definition, f, indent=1)
    os.replace(tmp, os.path.join(a.out, DEFINITION))

    order = []
    todo = []
    for values in itertools.product(*[g.values() for g in grids]):
        for m in methods:
            key = point_key(m, values)
            order.append(key)
            if key not in done:
                todo.append((key, point_sets(a.set, grids, values, m)))
    if done:
        print(f"sweep.py: {a.out}: {len(order) - len(todo)} of {len(order)} points already done", file=sys.stderr)
    rows = dict(done)
    failed = 0
    fd = os.open(path, os.O_WRONLY | os.O_APPEND)
    bar = Progress(len(todo), a.quiet)
    t0 = time.monotonic()
    cpu0 = children_cpu_s()
    try:
        for key, summary in Workers(a, min(a.jobs, max(1, len(todo)))).run(todo):
            row = row_of(key[0], [float(x) for x in key[1:]], summary)
            failed += row[-1] != STATUS_OK
            rows[key] = row
            os.write(fd, line_of(row).encode())
            bar.update()
    finally:
        os.close(fd)
        bar.close()
    wall = time.monotonic() - t0
    write_sorted(path, cols, [rows[k] for k in order if k in rows])
    if todo:
        cpu = children_cpu_s() - cpu0
        print(f"sweep.py: {len(todo)} points in {wall:.2f} s ({len(todo) / max(wall, 1e-9):.0f} points/s, "
              f"{a.jobs} jobs; drive_sil CPU {cpu:.2f} s, {1e3 * cpu / len(todo):.1f} ms a point) -> {path}",
              file=sys.stderr)
    if failed:
        print(f"sweep.py: {failed} point(s) failed to run (status column of {path})", file=sys.stderr)
        return 1
    return 0


def main(argv=None):
    a = parse_args(argv)
    try:
        return sweep(a)
    except BadInput as e:
        print(f"sweep.py: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("sweep.py: interrupted; run it again to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())

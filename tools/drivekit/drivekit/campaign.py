"""drive-campaign - a Monte Carlo robustness campaign of both methods on
your motor: N draws from the tolerance distributions of the motor file's
[campaign] section (defaults from the motor's data: CAMPAIGN_KEYS.md),
each run with the conventional and the proposed method on the same inputs
and judged by the rule over the judged window.

  drive-campaign MOTOR.ini --out DIR [--draws N] [--seed S]
                 [--scheduler local | dask-local | tcp://HOST:PORT] [--jobs N]

DIR/results.parquet   one row per draw: draw, inputs, both methods' figures
DIR/report.md         pass rate, advantage, worst draws, sensitivity, spec (PNGs beside it)
DIR/worst/*.ini       the worst draws as scenarios drive_sil runs as they are
                      (NAME_conv.ini / NAME_prop.ini pairs: rule-check DIR/worst)
DIR/campaign.json     what the results depend on (motor, seed, spec, drive_sil build)
DIR/parts/            the results as they come, one file per chunk of draws

A draw's inputs depend only on (seed, draw index). Run again with more
draws on the same DIR: only the new ones run; an interrupted campaign
keeps every finished chunk and resumes. Another motor file, seed, spec or
drive_sil build on the same DIR is refused (--fresh starts it anew).
Runs go to one drive_sil --batch process per chunk of draws: --jobs of
them at once on this machine (local), or as tasks of a Dask cluster
(tcp://HOST:PORT; dask-local starts one here with --jobs workers). The
last line: "campaign: N draws (M run now, K found), rule held in X ...".
Exit 0 done, 1 a draw or chunk failed in drive_sil, 2 bad input (nothing
written), 130 interrupted (finished chunks kept).
"""
import argparse
import hashlib
import importlib.util
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor, as_completed

from . import campaign_spec as cs
from . import campaign_worker

FORMAT = 1                         # of results and campaign.json; a change refuses an old DIR
DEFAULT_DRAWS = 500
DEFAULT_SEED = 1
DEFAULT_WORST = 5
CHUNK_MAX = 64                     # draws per drive_sil process at most
CHUNKS_PER_WORKER = 4              # at least this many chunks per worker, for balance
DASK_CONNECT_TIMEOUT = "20s"
SPEC_FILE = "campaign.json"
MOTOR_COPY = "motor.ini"
PARTS = "parts"
RESULTS = "results.parquet"
OURS = (SPEC_FILE, MOTOR_COPY, PARTS, RESULTS, "report.md", "campaign.png", "sensitivity.png", "worst")


class BadInput(Exception):
    """Exit 2: the message names the problem; nothing was written."""


# ---- results ------------------------------------------------------------------------------------

PER_METHOD_NUM = (("te_err", "te_err_Nm", "Nm"), ("te_ripple", "te_ripple_Nm", "Nm"),
                  ("speed_err", "speed_err_rpm", "rpm"), ("speed_err_max", "speed_err_max_rpm", "rpm"),
                  ("R_err", "R_err_pct", "pct"), ("L_err", "L_err_pct", "pct"),
                  ("psif_err", "psif_err_pct", "pct"), ("max_abs_i", "max_abs_i_A", "A"),
                  ("t_run", "t_run_s", "s"))
PER_METHOD_TEXT = (("state", "final_state_name"), ("fault", "fault_name"), ("warning", "warning"),
                   ("method_ran", "method_ran"), ("hold_reason", "hold_reason"), ("error", "error"))


def schema():
    import pyarrow as pa
    f = [pa.field("draw", pa.int64())]
    for c in cs.INPUT_COLUMNS:
        f.append(pa.field(c, pa.string() if c == "transient" else
                          pa.int64() if c == "encoder_lines" else pa.float64()))
    f += [pa.field("noise_seed", pa.int64()), pa.field("vdc_V", pa.float64()),
          pa.field("speed_rpm", pa.float64()), pa.field("load_Nm", pa.float64())]
    for m in cs.METHODS:
        f += [pa.field(f"{n}_{m}_{u}", pa.float64()) for n, _, u in PER_METHOD_NUM]
        f += [pa.field(f"held_share_{m}", pa.float64())]
        f += [pa.field(f"{n}_{m}", pa.string()) for n, _ in PER_METHOD_TEXT]
    f += [pa.field("rule_ok", pa.bool_()), pa.field("rule_why", pa.string()),
          pa.field("excess_Nm", pa.float64()), pa.field("advantage", pa.float64())]
    return pa.schema(f)


def _num(v):
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None


def judge(conv, prop):
    """(rule_ok, why, excess_Nm, advantage) of one draw: the rule of rule_check - the
    proposed method trips only where the conventional one does, and its mean |Te - Te*| is at most
    the conventional one's + 0.005 N m. None for a draw drive_sil refused or left unmeasured."""
    for name, s in (("conventional", conv), ("proposed", prop)):
        if s.get("error"):
            return None, f"{name}: {s['error']}", None, None
    cf, pf = conv["fault_name"] != "NONE", prop["fault_name"] != "NONE"
    if pf and not cf:
        return False, f"proposed trips ({prop['fault_name']}), conventional does not", None, None
    if pf or cf:
        return True, "both trip" if pf else "conventional trips", None, None
    c, p = _num(conv.get("te_err_Nm")), _num(prop.get("te_err_Nm"))
    if c is None or p is None or not (math.isfinite(c) and math.isfinite(p)):
        return None, "no rows in the window", None, None
    excess = p - c
    adv = c / p if p > 0 else None
    if excess > cs.RULE_MARGIN_NM:
        return False, f"proposed worse by {excess:.4f} N m", excess, adv
    return True, "", excess, adv


def make_row(draw, x, res):
    """One results row from the draw's inputs and the two summaries {"conv": ..., "prop": ...}."""
    row = {"draw": draw}
    row.update({c: x[c] for c in cs.INPUT_COLUMNS})
    row.update({k: x[k] for k in ("noise_seed", "vdc_V", "speed_rpm", "load_Nm")})
    for m, s in res.items():
        for n, key, u in PER_METHOD_NUM:
            row[f"{n}_{m}_{u}"] = _num(s.get(key))
        row[f"held_share_{m}"] = _num(s.get("held_share"))
        for n, key in PER_METHOD_TEXT:
            v = s.get(key)
            row[f"{n}_{m}"] = None if v is None else str(v)
    row["rule_ok"], row["rule_why"], row["excess_Nm"], row["advantage"] = judge(res["conv"], res["prop"])
    return row


def write_part(out, rows):
    import pyarrow as pa
    import pyarrow.parquet as pq
    d = os.path.join(out, PARTS)
    os.makedirs(d, exist_ok=True)
    first, last = rows[0]["draw"], rows[-1]["draw"]
    path = os.path.join(d, f"part-{first:09d}-{last:09d}-{len(rows)}.parquet")
    tmp = path + ".tmp"
    pq.write_table(pa.Table.from_pylist(rows, schema=schema()), tmp)
    os.replace(tmp, path)
    return path


def read_parts(out):
    """(table of every draw found in out/parts sorted by draw, part paths); a duplicate draw (a
    compaction cut short) counted once."""
    import numpy as np
    import pyarrow as pa
    import pyarrow.parquet as pq
    d = os.path.join(out, PARTS)
    paths = sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".parquet")) \
        if os.path.isdir(d) else []
    sch = schema()
    tables = []
    for p in paths:
        t = pq.read_table(p)
        if t.schema != sch:
            raise BadInput(f"{p}: other columns than this drive-campaign writes: start it anew (--fresh)")
        tables.append(t)
    if not tables:
        return sch.empty_table(), paths
    t = pa.concat_tables(tables)
    draws = t.column("draw").to_numpy()
    order = np.argsort(draws, kind="stable")
    keep = order[np.concatenate(([True], np.diff(draws[order]) != 0))] if len(order) else order
    return t.take(keep), paths


def compact(out, table, paths):
    """All parts as one file (the new one first, then the old ones removed)."""
    import pyarrow.parquet as pq
    if len(paths) <= 1:
        return
    d = os.path.join(out, PARTS)
    draws = table.column("draw").to_pylist()
    path = os.path.join(d, f"part-{draws[0]:09d}-{draws[-1]:09d}-{len(draws)}.parquet")
    tmp = path + ".tmp"
    pq.write_table(table, tmp)
    os.replace(tmp, path)
    for p in paths:
        if p != path:
            os.remove(p)


def write_atomic(path, data, mode="w"):
    tmp = f"{path}.tmp"
    with open(tmp, mode) as f:
        f.write(data)
    os.replace(tmp, path)


# ---- preparing: everything checked before anything is written ------------------------------------

def whole(text, what, least):
    """An int >= least from a command-line text, BadInput naming it."""
    try:
        n = int(str(text).strip(), 10)
    except ValueError:
        raise BadInput(f"{what} {text!r}: expected a whole number >= {least}") from None
    if n < least:
        raise BadInput(f"{what} {text}: expected a whole number >= {least}")
    return n


def check_out(out):
    """OUT must be a new directory, an empty one, or a campaign's: writable."""
    if os.path.exists(out):
        if not os.path.isdir(out):
            raise BadInput(f"--out {out}: exists and is no directory")
        if os.listdir(out) and not os.path.isfile(os.path.join(out, SPEC_FILE)):
            raise BadInput(f"--out {out}: a directory with other files and no {SPEC_FILE}: "
                           "name a new or empty directory")
        if not os.access(out, os.W_OK | os.X_OK):
            raise BadInput(f"--out {out}: not writable")
        return
    parent = os.path.dirname(os.path.abspath(out))
    while not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if not os.path.isdir(parent) or not os.access(parent, os.W_OK | os.X_OK):
        raise BadInput(f"--out {out}: cannot be created ({parent} is not a writable directory)")


def drive_sil_run(drive_sil, args, what):
    p = subprocess.run([drive_sil] + args, capture_output=True, text=True, check=False)
    if p.returncode not in (0, 3):
        msg = (p.stderr.strip() or p.stdout.strip() or f"exit {p.returncode}").splitlines()[0]
        raise BadInput(f"{what}: {msg}")
    return p


def motor_of(drive_sil, path, text):
    """motor_data() of the file: one run of it as it is with the proposed method (its trace in a
    temporary directory, for the resolved values)."""
    with tempfile.TemporaryDirectory(prefix="drive-campaign-") as tmp:
        csv, summ = os.path.join(tmp, "nominal.csv"), os.path.join(tmp, "nominal.json")
        drive_sil_run(drive_sil, ["--scenario", path, "--set", "controller.method=proposed",
                                  "--out", csv, "--summary", summ],
                      f"{path}: the proposed method does not run on it")
        with open(os.path.join(tmp, "nominal.resolved.json")) as f:
            resolved = json.load(f)
        with open(summ) as f:
            nominal = json.load(f)
    return cs.motor_data(resolved, nominal, text)


def prepare(a):
    """Everything the campaign needs, checked: a dict (plan). BadInput otherwise."""
    draws = whole(a.draws, "--draws", 1)
    seed = whole(a.seed, "--seed", 0)
    jobs = whole(a.jobs, "--jobs", 1)
    worst = whole(a.worst, "--worst", 0)
    chunk = whole(a.chunk, "--chunk", 1) if a.chunk is not None else None
    if not (a.scheduler in ("local", "dask-local") or a.scheduler.startswith("tcp://")):
        raise BadInput(f"--scheduler {a.scheduler}: expected local, dask-local or tcp://HOST:PORT")
    if not os.path.isfile(a.motor):
        raise BadInput(f"{a.motor}: no such motor file")
    try:
        with open(a.motor, encoding="utf-8") as f:
            text = f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise BadInput(f"{a.motor}: cannot read it: {e}") from None
    if not (os.path.isfile(a.drive_sil) and os.access(a.drive_sil, os.X_OK)):
        raise BadInput(f"--drive-sil {a.drive_sil}: not an executable (make build/host/drive_sil)")
    check_out(a.out)
    try:
        cs.check_section(a.motor, text)
    except cs.SpecError as e:
        raise BadInput(str(e)) from None
    version = drive_sil_run(a.drive_sil, ["--version"], "drive_sil --version").stdout.strip()
    try:
        spec = cs.Spec(a.motor, text, motor_of(a.drive_sil, a.motor, text))
    except cs.SpecError as e:
        raise BadInput(str(e)) from None
    # draw 0 and the corners (every input at its low end, at its high end) as drive_sil takes them
    for what, x in (("draw 0", spec.inputs(seed, 0)),
                    ("the distributions' low ends", spec.corner(cs.CORNER_U)),
                    ("the distributions' high ends", spec.corner(1 - cs.CORNER_U))):
        for m, msets in cs.METHODS.items():
            args = ["--scenario", a.motor, "--check", "--window", spec.window]
            for s in spec.overrides(x) + msets:
                args += ["--set", s]
            drive_sil_run(a.drive_sil, args, f"{what} ({cs.METHOD_NAMES[m]}): drive_sil refuses them")
    ident = {"format": FORMAT, "motor": os.path.abspath(a.motor), "motor_sha256": hashlib.sha256(
        text.encode()).hexdigest(), "seed": seed, "spec": spec.as_dict(), "methods": cs.METHODS,
        "drive_sil_sha256": campaign_worker.sha256_file(a.drive_sil), "drive_sil_version": version}
    spec_path = os.path.join(a.out, SPEC_FILE)
    if os.path.isfile(spec_path) and not a.fresh:
        try:
            with open(spec_path) as f:
                old = json.load(f)
        except (OSError, ValueError) as e:
            raise BadInput(f"{spec_path}: unreadable ({e}): start it anew with --fresh") from None
        diff = describe_change(old, ident)
        if diff:
            raise BadInput(f"--out {a.out} holds another campaign ({diff}): name another --out, or "
                           "start it anew with --fresh (make campaign FRESH=1)")
    return {"draws": draws, "seed": seed, "jobs": jobs, "worst": worst, "chunk": chunk, "text": text,
            "spec": spec, "ident": ident, "version": version}


def describe_change(old, new):
    """What differs between two campaign.json identities, as text ("" if nothing)."""
    out = []
    for k in ("format", "motor_sha256", "seed", "methods", "drive_sil_sha256"):
        if old.get(k) != new.get(k):
            what = {"motor_sha256": "the motor file's text", "drive_sil_sha256": "the drive_sil build"}.get(k, k)
            out.append(what if k.endswith("sha256") else f"{what} {old.get(k)} -> {new.get(k)}")
    ok, nk = old.get("spec", {}).get("keys", {}), new["spec"]["keys"]
    for k in nk:
        if ok.get(k) != nk[k]:
            out.append(f"[campaign] {k} '{ok.get(k)}' -> '{nk[k]}'")
    return "; ".join(out)


# ---- running ----------------------------------------------------------------------------------------

def chunks_of(todo, jobs, chunk):
    size = chunk or max(1, min(CHUNK_MAX, math.ceil(len(todo) / (jobs * CHUNKS_PER_WORKER))))
    return [todo[i:i + size] for i in range(0, len(todo), size)]


def job_of(plan, draws, drive_sil_ref):
    spec, seed = plan["spec"], plan["seed"]
    points, inputs = [], {}
    for d in draws:
        x = spec.inputs(seed, d)
        inputs[d] = x
        sets = spec.overrides(x)
        for m, msets in cs.METHODS.items():
            points.append([f"{d}:{m}", sets + msets])
    job = {"drive_sil": drive_sil_ref, "window": spec.window, "points": points,
           "scenario": {"sha256": plan["ident"]["motor_sha256"], "text": plan["text"]}}
    return job, inputs


class Progress:
    """tqdm on stderr (rate, time left) when it is a terminal and not --quiet."""

    def __init__(self, total, quiet):
        self.bar = None
        if not quiet and total and sys.stderr.isatty():
            from tqdm import tqdm
            self.bar = tqdm(total=total, unit="draw", file=sys.stderr, smoothing=0.1, dynamic_ncols=True)

    def update(self, n):
        if self.bar is not None:
            self.bar.update(n)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def run_local(tasks, jobs, on_done):
    """Each task (job, draws) in a pool of `jobs` threads, each driving one drive_sil at a time."""
    ex = ThreadPoolExecutor(max_workers=jobs)
    futs = {ex.submit(campaign_worker.run_chunk, job): (job, inputs) for job, inputs in tasks}
    done = set()
    try:
        for f in as_completed(futs):
            done.add(f)
            on_done(futs[f], f.result())
    except BaseException:
        ex.shutdown(wait=True, cancel_futures=True)
        for f in futs:          # chunks that finished meanwhile are kept
            if f not in done and f.done() and not f.cancelled() and f.exception() is None:
                on_done(futs[f], f.result())
        raise
    ex.shutdown(wait=True)


def worker_module(client, tmp):
    """campaign_worker as a top-level module named by its hash, uploaded to the scheduler and the
    workers (client.upload_file: they import it) and imported here under the same name, so its
    run_chunk pickles by reference on every side and no node needs drivekit installed."""
    with open(campaign_worker.__file__, "rb") as f:
        src = f.read()
    name = f"drivekit_campaign_worker_{hashlib.sha256(src).hexdigest()[:12]}"
    path = os.path.join(tmp, name + ".py")
    with open(path, "wb") as f:
        f.write(src)
    client.upload_file(path)
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        sys.modules[name] = module
    return sys.modules[name]


class DaskRunner:
    """A Dask cluster for the tasks: tcp://HOST:PORT, or dask-local (a LocalCluster of --jobs worker
    processes), connected before the campaign writes anything. drive_sil goes as the client's bytes
    (scattered once to each worker) unless --worker-drive-sil names it on the workers."""

    def __init__(self, a, jobs):
        import logging

        from distributed import Client, LocalCluster
        self.a, self.cluster, self.client = a, None, None
        self.tmp = tempfile.TemporaryDirectory(prefix="drive-campaign-")
        try:
            if a.scheduler == "dask-local":
                # on the loopback only; its HTTP server on a free port (none is fixed here)
                self.cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                            host="127.0.0.1", dashboard_address="127.0.0.1:0",
                                            silence_logs=logging.ERROR)
            self.client = Client(self.cluster if self.cluster is not None else a.scheduler,
                                 timeout=DASK_CONNECT_TIMEOUT)
            self.worker = worker_module(self.client, self.tmp.name)
        except (OSError, TimeoutError) as e:
            self.close()
            raise BadInput(f"--scheduler {a.scheduler}: {e}") from None

    def run(self, tasks, on_done):
        from distributed import as_completed as dask_completed
        data = None
        if self.a.worker_drive_sil is None:
            with open(self.a.drive_sil, "rb") as f:
                data = self.client.scatter(f.read(), broadcast=True, hash=False)
        futs = {self.client.submit(self.worker.run_chunk, job, data, pure=False): (job, inputs)
                for job, inputs in tasks}
        try:
            for f in dask_completed(list(futs)):
                on_done(futs[f], f.result())
        except BaseException:
            self.client.cancel(list(futs))
            raise

    def close(self):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        self.tmp.cleanup()


# ---- main -------------------------------------------------------------------------------------------

def parse_args(argv):
    ap = argparse.ArgumentParser(prog="drive-campaign", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("motor", nargs="?", help="the motor (scenario) file, with or without a [campaign] section")
    ap.add_argument("--out", metavar="DIR")
    ap.add_argument("--draws", default=str(DEFAULT_DRAWS), metavar="N", help=f"draws (default {DEFAULT_DRAWS})")
    ap.add_argument("--seed", default=str(DEFAULT_SEED), metavar="S", help=f"seed (default {DEFAULT_SEED})")
    ap.add_argument("--scheduler", default="local", help="local (default), dask-local or tcp://HOST:PORT")
    ap.add_argument("--jobs", default=str(os.cpu_count() or 1), metavar="N",
                    help="drive_sil processes at once (local) or dask-local workers (default: the cores)")
    ap.add_argument("--chunk", default=None, metavar="N", help="draws per drive_sil process (default: auto)")
    ap.add_argument("--drive-sil", default=os.environ.get("DRIVE_SIL", os.path.join("build", "host", "drive_sil")))
    ap.add_argument("--worker-drive-sil", default=None, metavar="PATH",
                    help="Dask: drive_sil at PATH on the workers (checked to be the same build) instead of "
                         "shipping the client's")
    ap.add_argument("--worst", default=str(DEFAULT_WORST), metavar="K", help="reproducers per method (default 5)")
    ap.add_argument("--fresh", action="store_true", help="start the campaign in --out anew")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    ap.add_argument("--list-keys", action="store_true", help="the [campaign] keys (--markdown: CAMPAIGN_KEYS.md)")
    ap.add_argument("--markdown", action="store_true", help=argparse.SUPPRESS)
    return ap.parse_args(argv)


def clear_ours(out):
    """--fresh: what a campaign writes into out, removed (nothing else)."""
    for name in OURS:
        p = os.path.join(out, name)
        if os.path.isdir(p):
            shutil.rmtree(p)
        elif os.path.exists(p):
            os.remove(p)


def campaign(a):
    plan = prepare(a)
    runner = DaskRunner(a, plan["jobs"]) if a.scheduler != "local" else None
    try:
        return run_campaign(a, plan, runner)
    finally:
        if runner is not None:
            runner.close()


def open_out(a, plan):
    """run_campaign's first step: a.out made (--fresh: our files in it removed), the campaign's
    identity and motor file written, the parts an interrupt caught half-written removed."""
    out = a.out
    os.makedirs(out, exist_ok=True)
    if a.fresh:
        clear_ours(out)
    write_atomic(os.path.join(out, SPEC_FILE), json.dumps(plan["ident"], indent=1) + "\n")
    write_atomic(os.path.join(out, MOTOR_COPY), plan["text"])
    for f in os.listdir(os.path.join(out, PARTS)) if os.path.isdir(os.path.join(out, PARTS)) else []:
        if f.endswith(".tmp"):          # a part an interrupt caught half-written
            os.remove(os.path.join(out, PARTS, f))


def print_speed(ran, dt, cpu, plan, runner, scheduler):
    """The closing figures of the draws run now: draws per second (per core when local)."""
    per_core = f"; {cpu:.1f} CPU-s: {ran / cpu:.1f} draws/s per core" if runner is None else ""
    how = f"{plan['jobs']} local {'job' if plan['jobs'] == 1 else 'jobs'}" if runner is None else scheduler
    print(f"campaign: ran {ran} draws in {dt:.1f} s ({how}): {ran / dt:.1f} draws/s{per_core}")


def finish(a, plan, ran):
    """run_campaign's last step: the parts compacted, the first plan["draws"] draws into results.parquet,
    the report (campaign_report.write) and the closing line; the exit status (1: a draw refused)."""
    out, n = a.out, plan["draws"]
    table, paths = read_parts(out)
    compact(out, table, paths)
    import pyarrow.compute as pc
    import pyarrow.parquet as pq
    results = table.filter(pc.less(table.column("draw"), n))
    write_table_atomic(pq, results, os.path.join(out, RESULTS))
    from . import campaign_report
    summary = campaign_report.write(out, results, plan, a)
    errors = summary["errors"]
    print(f"campaign: {n} draws ({ran} run now, {n - ran} found), rule held in "
          f"{summary['held']} ({summary['held_pct']:.1f} %), proposed worse in {summary['worse']}, tripped "
          f"alone in {summary['trips']}, advantage median {summary['adv_median_text']}"
          f"{f', {errors} refused by drive_sil' if errors else ''} -> {os.path.join(out, 'report.md')}")
    return 1 if errors else 0


def run_campaign(a, plan, runner):
    """The campaign of plan into a.out: the draws not found there run (locally, or on runner), each
    chunk's rows kept as it finishes, then finish(); the exit status (130: interrupted)."""
    out, n = a.out, plan["draws"]
    open_out(a, plan)
    table, _ = read_parts(out)
    found = set(table.column("draw").to_pylist())
    todo = [d for d in range(n) if d not in found]
    sha = plan["ident"]["drive_sil_sha256"]
    ref = {"sha256": sha, "path": os.path.abspath(a.worker_drive_sil or a.drive_sil)}
    tasks = [job_of(plan, ch, ref) for ch in chunks_of(todo, plan["jobs"], plan["chunk"])]
    bar = Progress(len(todo), a.quiet)
    state = {"ran": 0}
    t_start, cpu_start = time.monotonic(), cpu_seconds()

    def on_done(task, res):
        job, inputs = task
        rows = [make_row(d, inputs[d], {m: res[f"{d}:{m}"] for m in cs.METHODS}) for d in sorted(inputs)]
        write_part(out, rows)
        state["ran"] += len(rows)
        bar.update(len(rows))

    try:
        if tasks and runner is None:
            run_local(tasks, plan["jobs"], on_done)
        elif tasks:
            runner.run(tasks, on_done)
    except KeyboardInterrupt:
        bar.close()
        print(f"campaign: interrupted: {len(found) + state['ran']} of {n} draws kept in {out}/{PARTS}; "
              "run it again to resume", file=sys.stderr)
        return 130
    except Exception as e:    # a chunk's drive_sil failed, or the cluster did: the finished ones are kept
        bar.close()
        print(f"drive-campaign: {e}; {len(found) + state['ran']} of {n} draws kept: run it again to resume",
              file=sys.stderr)
        return 1
    bar.close()
    if state["ran"]:
        print_speed(state["ran"], time.monotonic() - t_start, cpu_seconds() - cpu_start, plan, runner, a.scheduler)
    return finish(a, plan, state["ran"])

def cpu_seconds():
    """CPU time of this process and its finished children (the drive_sil runs of the local pool)."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def write_table_atomic(pq, table, path):
    tmp = path + ".tmp"
    pq.write_table(table, tmp)
    os.replace(tmp, path)


def main(argv=None):
    a = parse_args(argv)
    if a.list_keys:
        if a.markdown:
            sys.stdout.write(cs.keys_markdown())
        else:
            for k in cs.KEYS:
                print(f"  {k.name:26s} {k.doc:40s} {k.meaning}")
        return 0
    if a.motor is None or a.out is None:
        print("drive-campaign: name the motor file and --out DIR (drive-campaign --help)", file=sys.stderr)
        return 2
    try:
        return campaign(a)
    except BadInput as e:
        print(f"drive-campaign: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:     # stdout closed early (| head): the campaign's files are written
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


if __name__ == "__main__":
    sys.exit(main())

"""One chunk of a campaign's runs in one drive_sil --batch process: what a
local worker thread or a Dask worker executes. Standard library only, so a
Dask worker needs no drivekit: the client sends this module by value.

A job is a dict:
  drive_sil  {"sha256": H, "path": P} (a file the worker has: checked
             against H) or {"sha256": H, "data": BYTES} (the client's own
             build, written once per worker into its temporary directory)
  scenario   {"sha256": H, "text": T} (the motor file, written likewise)
  window     "T0:T1", the judged window of every run
  points     [[ID, [section.key=value, ...]], ...]
run_chunk(job) returns {ID: summary dict} with drive_sil's figures
(tools/sil/summary.h), or raises RuntimeError when drive_sil fails.
"""
import hashlib
import json
import os
import subprocess
import tempfile

# Summary fields kept for the results (the rest stays on the worker).
FIELDS = ("id", "error", "final_state_name", "fault_name", "warning", "t_run_s", "max_abs_i_A",
          "te_err_Nm", "te_ripple_Nm", "speed_err_rpm", "speed_err_max_rpm", "R_err_pct", "L_err_pct",
          "psif_err_pct", "window_rows", "method_ran", "held_share", "hold_reason")

_checked = {}       # path -> (size, mtime, sha256) of a drive_sil already hashed


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _cached_file(sha256, data, name, mode):
    """A private copy of data under the worker's temporary directory, named by its hash."""
    d = os.path.join(tempfile.gettempdir(), f"drivekit-{os.getuid()}")
    os.makedirs(d, mode=0o700, exist_ok=True)
    path = os.path.join(d, f"{sha256[:16]}-{name}")
    if not os.path.exists(path):
        fd, tmp = tempfile.mkstemp(dir=d, prefix=f"{sha256[:16]}-", suffix=".tmp")
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    return path


def executable(spec):
    """The path of the job's drive_sil on this worker, checked to be the client's build."""
    if "data" in spec:
        return _cached_file(spec["sha256"], spec["data"], "drive_sil", 0o700)
    path = spec["path"]
    try:
        st = os.stat(path)
    except OSError as e:
        raise RuntimeError(f"drive_sil {path}: not on this worker ({e.strerror})") from None
    key = (st.st_size, st.st_mtime_ns)
    if _checked.get(path, (None,))[:2] != key:
        _checked[path] = key + (sha256_file(path),)
    if _checked[path][2] != spec["sha256"]:
        raise RuntimeError(f"drive_sil {path}: another build than the client's (sha256 {_checked[path][2][:12]} "
                           f"!= {spec['sha256'][:12]})")
    return path


def run_chunk(job, drive_sil_data=None):
    """Run the job's points through one drive_sil --batch; {ID: summary}. drive_sil_data: the
    build's bytes when the client shipped them separately (Dask scatters them once per worker)."""
    spec = dict(job["drive_sil"])
    if drive_sil_data is not None:
        spec["data"] = drive_sil_data
    exe = executable(spec)
    scen = _cached_file(job["scenario"]["sha256"], job["scenario"]["text"].encode(), "motor.ini", 0o600)
    lines = "".join("\t".join([pid] + sets) + "\n" for pid, sets in job["points"])
    p = subprocess.run([exe, "--scenario", scen, "--batch", "--window", job["window"]],
                       input=lines, capture_output=True, text=True, check=False)
    if p.returncode != 0:
        raise RuntimeError(f"drive_sil --batch exit {p.returncode}: {p.stderr.strip()[:300]}")
    out = {}
    for line in p.stdout.splitlines():
        d = json.loads(line)
        out[d.get("id")] = {k: d[k] for k in FIELDS if k in d}
    missing = [pid for pid, _ in job["points"] if pid not in out]
    if missing:
        raise RuntimeError(f"drive_sil --batch answered no line for {missing[0]} "
                           f"({len(missing)} missing): {p.stderr.strip()[:300]}")
    return out

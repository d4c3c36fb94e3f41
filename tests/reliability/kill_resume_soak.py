"""Kill-and-resume soak: a small suspension run killed with SIGKILL again and again, at
random moments and inside the write windows, and resumed each time; its final
summary.json and time series must equal an uninterrupted run's to the last bit.

Random moments rarely fall inside a write, so most kills are aimed: capsim's testing aid
CAPSIM_TEST_KILL_AT=<point>:<k> (docs/reliability.md) makes it raise SIGKILL on itself
the k-th time it passes <point>:
  series_written      rows appended to timeseries.h5.tmp, the file still open
  series_renamed      timeseries.h5 replaced, checkpoint.h5 not yet
  checkpoint_written  checkpoint.h5.tmp filled, the file still open
  checkpoint_closed   checkpoint.h5.tmp closed, not yet renamed over checkpoint.h5
A random kill is classed by the files it leaves: a checkpoint.h5.tmp or timeseries.h5.tmp
newer than checkpoint.h5 means it landed inside that write, else between writes.

Usage: .venv/bin/python tests/reliability/kill_resume_soak.py [--kills 24] [--seed 1]
           [--capsim PATH]
Writes results/reliability/kill_resume_soak.json.
"""

import argparse
import json
import os
import pathlib
import random
import signal
import subprocess
import tempfile
import time

import h5py
import numpy as np

from pipeline.command_line import run_command

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "results" / "reliability"
POINTS = ["series_written", "series_renamed", "checkpoint_written", "checkpoint_closed"]
# Two capsules in a periodic box, a checkpoint every 0.1 strain (about two steps), one
# thread: about 0.03 s per step here.
CASE = {"method": "direct", "phi": 0.05, "capsules": 2, "mesh_level": 1, "t_end": 12,
        "t_avg_start": 1, "output.checkpoint_interval": 0.1,
        "output.snapshot_interval": 1, "threads": 1}
# summary.json fields that describe the invocation, not the run.
INVOCATION_FIELDS = {"wall_seconds", "cpu_seconds", "resumed"}


def command(capsim, folder, case):
    """capsim on `folder`: a new run until it has a checkpoint, then a resume."""
    if (folder / "checkpoint.h5").exists():
        return [str(capsim), "run", "-q", "--resume", str(folder)]
    return run_command(capsim, case, folder, "-q")


def start(capsim, folder, case, kill_at=None):
    """Starts `command`, killed at the testing aid's point `kill_at` when given."""
    env = dict(os.environ)
    env.pop("CAPSIM_TEST_KILL_AT", None)
    if kill_at:
        env["CAPSIM_TEST_KILL_AT"] = kill_at
    return subprocess.Popen(command(capsim, folder, case), env=env, stderr=subprocess.PIPE,
                            text=True)


def window_of_random_kill(folder):
    """Where a kill at a random moment landed, from the files it left."""
    checkpoint = folder / "checkpoint.h5"
    done = checkpoint.stat().st_mtime_ns if checkpoint.exists() else 0
    for name, window in [("checkpoint.h5.tmp", "random_in_checkpoint"),
                         ("timeseries.h5.tmp", "random_in_series")]:
        tmp = folder / name
        if tmp.exists() and tmp.stat().st_mtime_ns >= done:
            return window
    return "random_between_writes"


def plan_kills(kills, rng, points):
    """Half aimed at the write windows `points` in turn, half at random moments."""
    plan = []
    for i in range(kills):
        if i % 2 == 0:
            plan.append((points[(i // 2) % len(points)], rng.randint(1, 3)))
        else:
            plan.append(("random", rng.uniform(0.02, 0.3)))
    return plan


def one_kill(capsim, folder, case, what, arg, log):
    """Starts capsim, kills it as planned; returns the window it died in, or None when
    the run ended first."""
    resume = (folder / "checkpoint.h5").exists()
    if what == "random":
        proc = start(capsim, folder, case)
        time.sleep(arg)
        proc.send_signal(signal.SIGKILL)
    else:
        proc = start(capsim, folder, case, f"{what}:{arg}")
    _, err = proc.communicate()
    if proc.returncode != -signal.SIGKILL:
        if proc.returncode != 0:
            raise RuntimeError(f"capsim failed (exit {proc.returncode}): {err}")
        log.append({"plan": what, "resume": resume, "landed": None})
        return None
    window = window_of_random_kill(folder) if what == "random" else what
    log.append({"plan": what, "arg": arg, "resume": resume, "landed": window})
    return window


def series_arrays(folder):
    out = {}
    with h5py.File(folder / "timeseries.h5", "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()])
                     if isinstance(obj, h5py.Dataset) else None)
    return out


def differences(whole, killed):
    """Names of what differs between the two run folders, bit for bit."""
    diff = []
    a, b = (json.loads((d / "summary.json").read_text()) for d in (whole, killed))
    for key in sorted(set(a) | set(b)):
        if key not in INVOCATION_FIELDS and a.get(key) != b.get(key):
            diff.append(f"summary.json: {key}")
    sa, sb = series_arrays(whole), series_arrays(killed)
    for name in sorted(set(sa) | set(sb)):
        x, y = sa.get(name), sb.get(name)
        if x is None or y is None or x.shape != y.shape or x.tobytes() != y.tobytes():
            diff.append(f"timeseries.h5: {name}")
    return diff


def soak(capsim, workdir, kills, seed, case=CASE, points=POINTS):
    """Runs the soak in `workdir`; returns the record written to the JSON."""
    rng = random.Random(seed)
    whole, killed = workdir / "whole", workdir / "killed"
    began = time.time()
    subprocess.run(run_command(capsim, case, whole, "-q"), check=True)
    log, windows = [], {}
    for what, arg in plan_kills(kills, rng, points):
        window = one_kill(capsim, killed, case, what, arg, log)
        if window:
            windows[window] = windows.get(window, 0) + 1
        if (killed / "summary.json").exists():
            break  # the run reached its end before this kill
    final = start(capsim, killed, case)
    _, err = final.communicate()
    if final.returncode != 0:
        raise RuntimeError(f"the last resume failed (exit {final.returncode}): {err}")
    diff = differences(whole, killed)
    leftovers = sorted(p.name for p in killed.glob("*.tmp"))
    return {
        "case": case, "seed": seed, "kills_tried": len(log),
        "kills_landed": sum(1 for e in log if e["landed"]),
        "kills_after_the_end": sum(1 for e in log if not e["landed"]),
        "windows": windows, "resumes": sum(1 for e in log if e["resume"]) + 1,
        "new_starts": sum(1 for e in log if not e["resume"]),
        "equal_to_uninterrupted": not diff, "differences": diff,
        "tmp_files_left": leftovers, "seconds": round(time.time() - began, 1),
        "log": log,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--kills", type=int, default=24)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--capsim", type=pathlib.Path, default=ROOT / "build" / "capsim")
    a = p.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        record = soak(a.capsim, pathlib.Path(tmp), a.kills, a.seed)
    path = OUT / "kill_resume_soak.json"
    path.write_text(json.dumps(record, indent=1))
    print(json.dumps({k: v for k, v in record.items() if k != "log"}, indent=1))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

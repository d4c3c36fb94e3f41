"""Full disks and damaged files: the small suspension run of kill_resume_soak.py
  1. on a file system that fills up: a tmpfs of --tmpfs-kb (needs root to mount; skipped
     otherwise) pre-filled so that --cases different amounts of free space stop the run
     at different writes (run.yaml, time series, snapshot, checkpoint, summary). Each
     stop must be exit 4 with one message, leave a readable checkpoint (or none yet), and,
     once space is freed, resume (or restart) to the uninterrupted run's bits;
  2. with timeseries.h5 damaged after a kill: 16 bytes flipped at --cases offsets spread
     over the file, and the file cut to a few lengths. Each resume must either refuse with
     one message naming the file and change nothing (detected), or finish equal to the
     uninterrupted run (the bytes were unused space): never a different result.

Usage: sudo .venv/bin/python tests/reliability/disk_faults.py [--cases 30] [--capsim PATH]
Writes results/reliability/disk_faults.json.
"""

import argparse
import json
import os
import pathlib
import shutil
import signal
import subprocess
import tempfile

from pipeline.command_line import run_command

from kill_resume_soak import CASE, command, differences

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "results" / "reliability"
SMALL = {**CASE, "t_end": 3, "output.snapshot_interval": 1}


def capsim(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def where_it_failed(message):
    for key in ["run.yaml", "timeseries", "snapshot", "checkpoint", "summary"]:
        if f"cannot write {key}" in message or f"{key}.tmp" in message or (
                key in message and "cannot" in message.split(key)[0][-40:]):
            return key
    return "other"


def finish(exe, run):
    """Resumes a stopped run, or starts it again when it has no checkpoint yet."""
    return capsim(command(exe, run, SMALL))


def full_disk_case(exe, mount, whole, free):
    filler = mount / "filler"
    shutil.rmtree(mount / "run", ignore_errors=True)
    filler.unlink(missing_ok=True)
    stat = os.statvfs(mount)
    with open(filler, "wb") as f:
        f.write(bytes(max(0, stat.f_bavail * stat.f_frsize - free)))
    run = mount / "run"
    r = capsim(run_command(exe, SMALL, run, "-q"))
    case = {"free_bytes": free, "exit": r.returncode, "message": r.stderr.strip()}
    if r.returncode == 0:
        case["outcome"] = "finished"
        return case
    case["failed_at"] = where_it_failed(r.stderr)
    case["one_line"] = r.stderr.strip().count("\n") == 0 and "HDF5-DIAG" not in r.stderr
    case["tmp_files_left"] = sorted(p.name for p in run.glob("*.tmp"))
    filler.unlink()
    done = finish(exe, run)
    case["resumed"] = done.returncode == 0
    case["equal_to_uninterrupted"] = done.returncode == 0 and not differences(whole, run)
    case["outcome"] = "ok" if (r.returncode == 4 and case["one_line"]
                               and case["equal_to_uninterrupted"]) else "FAILED"
    return case


def full_disk(exe, whole, cases, kb):
    mount = pathlib.Path(tempfile.mkdtemp(prefix="capsim_tmpfs_"))
    if subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={kb}k", "tmpfs", str(mount)],
                      capture_output=True).returncode != 0:
        mount.rmdir()
        return {"skipped": "cannot mount a tmpfs (not root?)"}
    try:
        top = 240_000  # the finished run takes about 180 kB
        frees = [int(top * (i + 1) / cases) for i in range(cases)]
        return {"tmpfs_kb": kb, "cases": [full_disk_case(exe, mount, whole, f)
                                          for f in frees]}
    finally:
        subprocess.run(["umount", str(mount)])
        mount.rmdir()


def killed_copy(exe, work):
    run = work / "killed"
    if not run.exists():
        env = dict(os.environ, CAPSIM_TEST_KILL_AT="checkpoint_closed:12")
        r = subprocess.run(run_command(exe, SMALL, run, "-q"), env=env)
        assert r.returncode == -signal.SIGKILL
    copy = work / "damaged"
    shutil.rmtree(copy, ignore_errors=True)
    shutil.copytree(run, copy)
    return copy


def files_of(folder):
    return {str(p): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def damage_case(exe, work, whole, damage, label):
    run = killed_copy(exe, work)
    damage(run / "timeseries.h5")
    before = files_of(run)
    r = capsim([str(exe), "run", "-q", "--resume", str(run)])
    case = {"damage": label, "exit": r.returncode, "message": r.stderr.strip()[:300]}
    if r.returncode == 0:
        same = not differences(whole, run)
        case["outcome"] = "harmless (resumed, equal)" if same else "FAILED (silent damage)"
    else:
        clear = (r.returncode == 4 and "timeseries.h5 is corrupt" in r.stderr
                 and r.stderr.strip().count("\n") == 0 and "HDF5-DIAG" not in r.stderr)
        unchanged = files_of(run) == before
        case["outcome"] = "detected" if clear and unchanged else "FAILED"
    return case


def flip(offset):
    def damage(path):
        with open(path, "r+b") as f:
            f.seek(offset)
            old = f.read(16)
            f.seek(offset)
            f.write(bytes(b ^ 0x5A for b in old))
    return damage


def damaged_files(exe, work, whole, cases):
    size = (killed_copy(exe, work) / "timeseries.h5").stat().st_size
    out = [damage_case(exe, work, whole, flip(size * i // cases), f"flip 16 bytes at "
                       f"{size * i // cases} of {size}") for i in range(cases)]
    for fraction in [0.9, 0.5, 0.1]:
        cut = int(size * fraction)
        out.append(damage_case(exe, work, whole, lambda p, c=cut: os.truncate(p, c),
                               f"cut to {cut} of {size} bytes"))
    return out


def tally(cases, key="outcome"):
    counts = {}
    for c in cases:
        counts[c[key]] = counts.get(c[key], 0) + 1
    return counts


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", type=int, default=30)
    p.add_argument("--tmpfs-kb", type=int, default=1024)
    p.add_argument("--capsim", type=pathlib.Path, default=ROOT / "build" / "capsim")
    a = p.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        whole = work / "whole"
        subprocess.run(run_command(a.capsim, SMALL, whole, "-q"), check=True)
        disk = full_disk(a.capsim, whole, a.cases, a.tmpfs_kb)
        damage = damaged_files(a.capsim, work, whole, a.cases)
    record = {"case": SMALL, "full_disk": disk, "damaged_timeseries": damage,
              "summary": {"full_disk": tally(disk.get("cases", [])),
                          "full_disk_failed_at": tally(
                              [c for c in disk.get("cases", []) if "failed_at" in c],
                              "failed_at"),
                          "damaged_timeseries": tally(damage)}}
    path = OUT / "disk_faults.json"
    path.write_text(json.dumps(record, indent=1))
    print(json.dumps(record["summary"], indent=1))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

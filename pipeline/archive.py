"""The results archive: compact, checksummed records of runs, kept in the repository
(archive/<configuration>/), from which the workflow restores a run instead of computing it.

A record is a folder <archive>/<study>/<name>/, the run folder's own path under results/:

    record.json      provenance: the run's key (pipeline.run_spec), physics version,
                     resolved options (run.yaml), how far it got, its segments (strain,
                     CPU and wall seconds, threads, machine, commit, date), the sha256 of
                     every other file, and the sha256 of its own content (`checksum`)
    run.yaml         capsim's resolved options
    timeseries.h5    every row of the time series, the capsule series in single precision
                     (compact_series())
    summary.json     a finished run only
    state.h5         a capsim checkpoint: the latest of an unfinished run (to continue
                     from); of a finished run, the start of its last segment (an audit
                     replays that segment and compares rows; raising t_end continues
                     from it), none where it ran in one segment; of a dilute run, its
                     end (figure 1 reads its capsule; a few kB)
    snapshot_*.h5    the last mesh snapshot, for runs that write snapshots (figure 2)

Why not Snakemake's own mechanisms: its between-workflow cache (`--cache`) stores whole
outputs under a hash of the rule's code, parameters and software environment, outside
the repository, and only for rules whose outputs are complete; it cannot hold half a run,
keep a record small, or be committed and reviewed. Storage plugins move files to remote
storage but do not decide which run is which. A record keyed by the run's own physics
(its options and the solver's physics version), checked file by file, in git, does.

    python -m pipeline.archive verify ARCHIVE_OR_RECORD...   check records (exit 1 if bad)
    python -m pipeline.archive list ARCHIVE...               one line per record
    python -m pipeline.archive replay --capsim C RECORD...   recompute the stretch after
                                                             each record's state, compare
"""

import argparse
import hashlib
import json
import math
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np
import yaml

from pipeline.run_spec import physics_version

FORMAT = 1
RECORD = "record.json"
SUMMARY, RUN_YAML, SERIES = "summary.json", "run.yaml", "timeseries.h5"
STATE = "state.h5"
CHECKPOINT = "checkpoint.h5"


class ArchiveError(RuntimeError):
    """A record that cannot be used: its checksum or format is wrong."""


def sha256(path):
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _content_checksum(record):
    content = {k: v for k, v in record.items() if k != "checksum"}
    text = json.dumps(content, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _checkpoint_time(path):
    with h5py.File(path, "r") as f:
        return float(f["time"][()])


def _copy_series(source, target, dtype, compress):
    """Copies a time series dataset by dataset, keeping attributes and fletcher32, the
    first axis extensible as capsim writes it; capsule/* in `dtype`."""
    with h5py.File(source, "r") as src, h5py.File(target, "w") as dst:
        dst.attrs.update(dict(src.attrs))

        def copy(name, obj):
            if not isinstance(obj, h5py.Dataset):
                return
            data = obj[()]
            if name.startswith("capsule/"):
                data = data.astype(dtype)
            chunks = (min(max(1, data.shape[0]), 4096 if compress else 64),) + data.shape[1:]
            extra = {"compression": "gzip", "compression_opts": 9, "shuffle": True} \
                if compress else {}
            out = dst.create_dataset(name, data=data, chunks=chunks,
                                     maxshape=(None,) + data.shape[1:], fletcher32=True,
                                     **extra)
            out.attrs.update(dict(obj.attrs))

        src.visititems(copy)


def compact_series(source, target):
    """The archive's form of a time series: time and step as they are, the capsule
    series in single precision (7 significant digits: the averages move by about 1e-8
    of themselves, six orders below their statistical error), gzip over shuffled bytes.
    About a quarter of capsim's file (double precision does not compress: 1.5 times)."""
    _copy_series(source, target, np.float32, compress=True)


def widen_series(source, target):
    """A record's time series back in capsim's form (double precision, its chunks), so
    that a restored run is read and continued like any other."""
    _copy_series(source, target, np.float64, compress=False)


def _last_snapshot(run_dir):
    files = sorted((Path(run_dir) / "snapshots").glob("snapshot_*.h5"))
    return files[-1] if files else None


def read_record(record_dir):
    """record.json of a record, checked: its format, its own checksum and the sha256 of
    every file it lists. Raises ArchiveError naming the record and what is wrong."""
    record_dir = Path(record_dir)
    path = record_dir / RECORD
    try:
        record = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise ArchiveError(f"archive record {record_dir}: {RECORD} cannot be read ({e})")
    if not isinstance(record, dict) or record.get("format") != FORMAT:
        raise ArchiveError(f"archive record {record_dir}: unknown format "
                           f"{record.get('format') if isinstance(record, dict) else '?'} "
                           f"(this version reads format {FORMAT})")
    if record.get("checksum") != _content_checksum(record):
        raise ArchiveError(f"archive record {record_dir}: {RECORD} does not match its "
                           "checksum (edited or damaged)")
    for name, digest in record["files"].items():
        file = record_dir / name
        if not file.is_file():
            raise ArchiveError(f"archive record {record_dir}: {name} is missing")
        if sha256(file) != digest:
            raise ArchiveError(f"archive record {record_dir}: {name} does not match its "
                               "sha256 in record.json (edited or damaged)")
    return record


def reached(run_dir):
    """How far a run folder got: (finished, t) with t the checkpoint's time, or the end
    of a finished run; None for a folder without a run."""
    run_dir = Path(run_dir)
    if (run_dir / SUMMARY).exists():  # its t_end: the last row (a stop's time)
        return True, float(json.loads((run_dir / SUMMARY).read_text())["t_end"] or 0)
    if (run_dir / CHECKPOINT).exists():
        return False, _checkpoint_time(run_dir / CHECKPOINT)
    return None


def collect(run_dir, record_dir, key, final_state=False):
    """Records the run folder in the archive (replacing an older record of it; a record
    of the same key that reached further is kept). final_state: a finished run keeps its
    last checkpoint as its state (a dilute run: figure 1 reads its capsule). Returns the
    record."""
    run_dir, record_dir = Path(run_dir), Path(record_dir)
    state = reached(run_dir)
    if state is None:
        raise ArchiveError(f"{run_dir}: no run to record (no summary.json, no checkpoint)")
    finished, t = state
    previous = None
    if (record_dir / RECORD).exists():
        try:
            previous = read_record(record_dir)
        except ArchiveError:
            previous = None  # a broken record is replaced
    if previous and previous["key"] == key and previous["t_reached"] > t:
        return previous
    tmp = record_dir.with_name(record_dir.name + ".tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    shutil.copyfile(run_dir / RUN_YAML, tmp / RUN_YAML)
    compact_series(run_dir / SERIES, tmp / SERIES)
    state_time = None
    if finished:
        shutil.copyfile(run_dir / SUMMARY, tmp / SUMMARY)
        audit = record_dir / STATE
        if final_state:
            shutil.copyfile(run_dir / CHECKPOINT, tmp / STATE)
            state_time = _checkpoint_time(run_dir / CHECKPOINT)
        elif (previous and previous["key"] == key and previous["state_time"] is not None
                and previous["state_time"] < t):  # the start of the last segment
            shutil.copyfile(audit, tmp / STATE)
            state_time = previous["state_time"]
    else:
        shutil.copyfile(run_dir / CHECKPOINT, tmp / STATE)
        state_time = t
    snapshot = _last_snapshot(run_dir)
    if snapshot is not None:
        shutil.copyfile(snapshot, tmp / snapshot.name)
    segments_file = run_dir / "segments.json"
    segments = json.loads(segments_file.read_text()) if segments_file.exists() else []
    summary = json.loads((run_dir / SUMMARY).read_text()) if finished else {}
    if not segments and summary:  # a run made outside the job: its last invocation only
        segments = [{"t_from": None, "t_to": t, "cpu_seconds": summary.get("cpu_seconds"),
                     "wall_seconds": summary.get("wall_seconds"),
                     "threads": summary.get("threads"), "machine": None,
                     "commit": None, "date": None}]
    options = yaml.safe_load((run_dir / RUN_YAML).read_text())
    with h5py.File(run_dir / SERIES, "r") as f:
        rows = int(f["time"].shape[0])
        t_last = float(f["time"][-1]) if rows else 0.0
    record = {
        "format": FORMAT, "key": key, "physics_version": physics_version(),
        "study": record_dir.parent.name, "name": record_dir.name,
        "finished": finished, "ended": summary.get("ended"),
        "t_end": options.get("t_end"), "t_avg_start": options.get("t_avg_start"),
        "t_reached": t, "rows": rows, "t_last_row": t_last, "state_time": state_time,
        "solver_version": summary.get("version"), "options": options,
        "segments": segments,
        "cpu_seconds": round(sum(s.get("cpu_seconds") or 0 for s in segments), 2),
        "files": {p.name: sha256(p) for p in sorted(tmp.iterdir())},
    }
    record["checksum"] = _content_checksum(record)
    (tmp / RECORD).write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
    old = record_dir.with_name(record_dir.name + ".old")
    shutil.rmtree(old, ignore_errors=True)
    if record_dir.exists():
        record_dir.rename(old)
    tmp.rename(record_dir)
    shutil.rmtree(old, ignore_errors=True)
    return record


def restore(record_dir, run_dir, record, full):
    """Writes a record into a run folder: everything a finished run's readers need when
    `full` (summary.json included), else the time series and the state to continue
    from (as checkpoint.h5) only."""
    record_dir, run_dir = Path(record_dir), Path(run_dir)
    shutil.rmtree(run_dir, ignore_errors=True)
    run_dir.mkdir(parents=True)
    shutil.copyfile(record_dir / RUN_YAML, run_dir / RUN_YAML)
    widen_series(record_dir / SERIES, run_dir / SERIES)
    if record["state_time"] is not None:
        shutil.copyfile(record_dir / STATE, run_dir / CHECKPOINT)
    for snapshot in record_dir.glob("snapshot_*.h5"):
        (run_dir / "snapshots").mkdir(exist_ok=True)
        shutil.copyfile(snapshot, run_dir / "snapshots" / snapshot.name)
    (run_dir / "segments.json").write_text(json.dumps(record["segments"], indent=1) + "\n")
    if full:
        shutil.copyfile(record_dir / SUMMARY, run_dir / SUMMARY)


def marker(run_dir, k):
    """The file that says segment k of a run is done (the output of its job)."""
    return Path(run_dir) / f"segment{k}.done"


def _usable(record, spec, key, current):
    """How a checked record serves a run: "full", "partial" (a state to continue from),
    or why not: "stale" (another physics version), "changed" (other options), None."""
    if record["physics_version"] != current:
        return "stale"
    if record["key"] != key:
        return "changed"
    if (record["finished"] and record["t_end"] == spec.t_end
            and record["t_avg_start"] == spec.t_avg_start):
        return "full"
    if record["state_time"] is not None and record["state_time"] < spec.t_end:
        return "partial"
    return None


def sync(specs, archive_root, segment_ends, workdir="."):
    """Brings the run folders of a configuration and its archive up to date with each
    other, before the workflow decides what to run: a record that reaches further than
    the folder is restored into it (a finished one whole; an unfinished one as its state,
    with the marker of its last segment done), and a folder that reaches further than
    the archive is recorded. segment_ends(spec): the pause times of the run's segments.
    Returns {"restored": [...], "partial": [...], "recorded": [...], "stale": [...],
    "changed": [...]} (run folders). Raises ArchiveError for a damaged record."""
    current = physics_version()
    report = {k: [] for k in ("restored", "partial", "recorded", "stale", "changed")}
    for spec in specs:
        run_dir = Path(workdir) / spec.folder
        record_dir = Path(archive_root) / spec.study / spec.name
        key = spec.key(current)
        record = read_record(record_dir) if (record_dir / RECORD).exists() else None
        use = _usable(record, spec, key, current) if record else None
        if use in ("stale", "changed"):
            report[use].append(spec.folder)
        local = reached(run_dir)
        if use == "full" and (local is None or not local[0]):
            restore(record_dir, run_dir, record, full=True)
            report["restored"].append(spec.folder)
        elif use == "partial" and (local is None or
                                   (not local[0] and local[1] < record["state_time"])):
            restore(record_dir, run_dir, record, full=False)
            done = [k for k, t in enumerate(segment_ends(spec)[:-1], 1)
                    if t <= record["state_time"]]
            if done:
                marker(run_dir, done[-1]).write_text(
                    json.dumps({"t": record["state_time"]}) + "\n")
            report["partial"].append(spec.folder)
        # A folder that reaches further is recorded, unless its run has not left t = 0.
        elif local is not None and (local[0] or local[1] > 0) and use != "full" and (
                use != "partial" or local[0] or local[1] > record["t_reached"]):
            collect(run_dir, record_dir, key, final_state=spec.dilute)
            report["recorded"].append(spec.folder)
    return report


# A replay by another build agrees to the record's rounding: a reordered sum moves the
# double values by about 1e-15, which flips the stored last place of a value at a
# rounding boundary by one unit; a change of the physics moves them further (the lighter
# quadrature of the present defaults: 1.5e-5 of the series within 2 strain units,
# docs/performance.md).
ROUNDING_UNITS = 1


def _units_apart(stored, replayed):
    """The largest difference of the replayed rows, rounded as the record stores them,
    from the stored ones, in units in the last place of the dataset's largest value or
    of 1, whichever is larger: the quantities are of order 1 in the solver's units, and
    one far below it (the volume drift, 1e-14) is round-off itself. Counts (the step,
    the repelled nodes) have no rounding: any difference is infinitely many units."""
    stored = np.asarray(stored)
    rounded = np.asarray(replayed).astype(stored.dtype).astype(np.float64)
    diff = np.max(np.abs(stored.astype(np.float64) - rounded), initial=0.0)
    if diff == 0:
        return 0.0
    if not np.issubdtype(stored.dtype, np.floating):
        return math.inf
    scale = max(float(np.max(np.abs(stored))), 1.0)
    return float(diff / np.spacing(stored.dtype.type(scale)))


def replay(record_dir, capsim, threads=None, span=None):
    """Recomputes a record's rows after its state: restores the state into a scratch
    folder, resumes capsim to the record's t_reached (or `span` strain units past the
    state: then the last row, which capsim writes wherever the run ends, is left out),
    and returns (rows compared, the largest difference over every dataset of those rows,
    the replayed rows rounded as the record stores them, in units in the last place of
    the record's values). The same build and thread count as the record's last segment
    (threads None) give the same reductions in the same order, so the difference is
    exactly 0; another thread count or a build that orders a sum otherwise (a vector
    clone, a cell width) changes the last bits of the sums (relative 1e-15 a step,
    growing with the steps replayed), which the record's rounding hides but for a value
    that lies at a rounding boundary: one unit."""
    record = read_record(record_dir)
    if record["state_time"] is None or record["state_time"] >= record["t_reached"]:
        raise ArchiveError(f"archive record {record_dir}: no state before its last row "
                           "to replay from")
    threads = threads or record["segments"][-1].get("threads") or 1
    t_end = record["t_reached"] if span is None else min(record["t_reached"],
                                                         record["state_time"] + span)
    with tempfile.TemporaryDirectory() as scratch:
        run_dir = Path(scratch) / "run"
        restore(record_dir, run_dir, record, full=False)
        # The averaging window only shapes the summary, not the rows; it opens at the
        # state so that a replay ending before the record's window (a state at t 0)
        # is still a valid run.
        done = subprocess.run([str(capsim), "run", "-q", "--resume", str(run_dir), "--set",
                               f"t_end={t_end}", "--set",
                               f"t_avg_start={record['state_time']}", "--set",
                               f"threads={threads}"], capture_output=True, text=True)
        if done.returncode != 0:
            raise ArchiveError(f"archive record {record_dir}: the replay failed "
                               f"(exit {done.returncode}): {done.stderr.strip()}")
        with h5py.File(record_dir / SERIES, "r") as a, \
                h5py.File(run_dir / SERIES, "r") as b:
            start = int(np.searchsorted(a["time"][()], record["state_time"], "right"))
            stop = a["time"].shape[0] if t_end == record["t_reached"] else \
                b["time"].shape[0] - 1
            if stop > a["time"].shape[0] or b["time"].shape[0] < stop:
                raise ArchiveError(f"archive record {record_dir}: the replay wrote "
                                   f"{b['time'].shape[0]} rows, the record holds "
                                   f"{a['time'].shape[0]}")
            names = []
            a.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset)
                         else None)
            # The record's capsule rows are single precision: the replayed rows are
            # rounded the same way before they are compared.
            diff = max(_units_apart(a[n][start:stop], b[n][start:stop]) for n in names)
            return stop - start, diff


def read_records(paths):
    """(folder, record) of every record under `paths`, checked (read_record)."""
    return [(path, read_record(path)) for path in _records(paths)]


def summary(records):
    """{"records", "finished", "bytes", "cpu_seconds", "physics_versions"} of (folder,
    record) pairs."""
    out = {"records": 0, "finished": 0, "bytes": 0, "cpu_seconds": 0.0,
           "physics_versions": set()}
    for path, record in records:
        out["records"] += 1
        out["finished"] += bool(record["finished"])
        out["bytes"] += sum(f.stat().st_size for f in path.iterdir())
        out["cpu_seconds"] += record["cpu_seconds"]
        out["physics_versions"].add(record["physics_version"])
    return out


def _records(paths):
    for path in map(Path, paths):
        if (path / RECORD).exists():
            yield path
        else:
            yield from sorted(p.parent for p in path.rglob(RECORD))


def main(argv=None):
    ap = argparse.ArgumentParser(description="Check or list the records of a results "
                                 "archive.")
    ap.add_argument("command", choices=["verify", "list", "replay"])
    ap.add_argument("paths", nargs="+", help="archive folders or records")
    ap.add_argument("--capsim", default=str(Path(__file__).resolve().parent.parent /
                                            "build" / "capsim"),
                    help="the solver, for replay (default build/capsim)")
    args = ap.parse_args(argv)
    bad, sound = 0, []
    current = physics_version()
    for path in _records(args.paths):
        try:
            record = read_record(path)
        except ArchiveError as e:
            print(e, file=sys.stderr)
            bad += 1
            continue
        sound.append((path, record))
        if args.command == "replay":
            if record["state_time"] is None or record["state_time"] >= record["t_reached"]:
                continue
            rows, diff = replay(path, args.capsim)
            print(f"{path}: {rows} rows from t {record['state_time']:g} replayed, largest "
                  f"difference {diff:.3g} units in the record's last place")
            bad += diff > ROUNDING_UNITS
        if args.command == "list":
            stale = "" if record["physics_version"] == current else " STALE"
            # A partial record counts the CPU of its finished segments only: the one it
            # stopped in reported none.
            state, cpu_of = (("finished", "") if record["finished"] else
                             ("partial", " in finished segments"))
            print(f"{path}: {state} t {record['t_reached']:g}/{record['t_end']:g}, "
                  f"{record['cpu_seconds']:.0f} CPU s{cpu_of}, key {record['key'][:12]}"
                  f"{stale}")
    if args.command == "verify":
        print(f"archive: {bad} bad record(s)" if bad else "archive: every record is sound")
    if args.command == "list" and not bad:
        total = summary(sound)
        print(f"archive: {total['records']} records, {total['bytes'] / 1e6:.1f} MB, "
              f"{total['cpu_seconds']:.0f} CPU s ({total['cpu_seconds'] / 3600:.1f} h)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

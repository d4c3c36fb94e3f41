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
                     from it), none where it ran in one segment, its end where it
                     lengthened a record without a state; of a dilute run, its end
                     (figure 1 reads its capsule; a few kB)
    snapshot_*.h5    the last mesh snapshot, for runs that write snapshots (figure 2)

Why not Snakemake's own mechanisms: its between-workflow cache (`--cache`) stores whole
outputs under a hash of the rule's code, parameters and software environment, outside
the repository, and only for rules whose outputs are complete; it cannot hold half a run,
keep a record small, or be committed and reviewed. Storage plugins move files to remote
storage but do not decide which run is which. A record keyed by the run's own physics
(its options and the solver's physics version), checked file by file, in git, does.

A record's identity comes from the record itself: its key is that of the options it
stores (run_spec.options_key()), and run.yaml, summary.json's parameters, the state's
options and the series' capsule count must all be those options; read_record() refuses
a record where they are not, or where a file is missing, damaged or not listed. The
checksums catch accidental damage and careless copies, not a forger with write access
to the repository (git history and review guard that). A record is only ever written
whole, replacing one of the same key: one of another physics version or of other
options is kept as it is (collect() refuses to replace it). Restores and recordings are
atomic (into a temporary folder, renamed into place) and serialised by a lock on the
archive folder itself (flock), which concurrent invocations share.

    python -m pipeline.archive verify ARCHIVE_OR_RECORD...   check records (exit 1 if bad),
                                                             and report files and folders
                                                             that are no record's
    python -m pipeline.archive list ARCHIVE...               one line per record
    python -m pipeline.archive replay --capsim C RECORD...   recompute the stretch after
                                                             each record's state, compare
"""

import argparse
import contextlib
import fcntl
import hashlib
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np
import yaml

from pipeline.command_line import resume_command
from pipeline.run_spec import flat_options, options_differ, options_key, physics_version

FORMAT = 1
RECORD = "record.json"
SUMMARY, RUN_YAML, SERIES = "summary.json", "run.yaml", "timeseries.h5"
STATE = "state.h5"
# Rows per compressed chunk of a record's series. A run taken further (a raised t_end, a
# segment more) is recorded again whole, but its earlier rows are the same, and so are
# their complete chunks byte for byte: git's packs store such a file as a delta of the
# last (a run recorded at four lengths: 4.26 MB packed against 4.18 MB for its last file
# alone; 6.56 MB in chunks of 4096 rows, about 190 strain units, which change until a
# run has passed them). Chunks of 256 rows (about 11 strain units) gzip 2 % larger.
CHUNK_ROWS = 256
CHECKPOINT = "checkpoint.h5"
# Written into a run folder restored from a record: the record, its key and physics
# version, and the sha256 of every file restored, so that the folder is known for what it
# is and checked against it (check_folder()).
RESTORED = "restored.json"
SEGMENTS = "segments.json"


class ArchiveError(RuntimeError):
    """A record or a run folder that cannot be used: the message names it and says what
    is wrong and what to do."""


@contextlib.contextmanager
def locked(folder):
    """Holds an exclusive lock on a folder (flock on the folder itself: nothing is
    written, so a read-only archive can be locked too) while every restore from and
    recording into it runs: concurrent invocations take turns."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def _new_folder(target):
    """An empty temporary folder beside `target`, to be renamed into place."""
    target.parent.mkdir(parents=True, exist_ok=True)
    return Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp",
                                 dir=target.parent))


def _replace(tmp, target):
    """Puts the folder tmp in the place of target (renames: the old one is gone only
    once the new one is there)."""
    old = None
    if target.exists():
        old = target.with_name(f".{target.name}.{os.getpid()}.old")
        target.rename(old)
    tmp.rename(target)
    if old is not None:
        shutil.rmtree(old)


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
            rows = CHUNK_ROWS if compress else 64
            chunks = (min(max(1, data.shape[0]), rows),) + data.shape[1:]
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
    """record.json of a record, checked: its format, its own checksum, the sha256 of
    every file it lists, that it lists every file there is, and its identity
    (check_identity()). Raises ArchiveError naming the record and what is wrong."""
    record_dir = Path(record_dir)
    try:
        record = json.loads((record_dir / RECORD).read_text())
        if not isinstance(record, dict) or record.get("format") != FORMAT:
            raise ArchiveError(
                f"unknown format {record.get('format') if isinstance(record, dict) else '?'}"
                f" (this version reads format {FORMAT})")
        if record.get("checksum") != _content_checksum(record):
            raise ArchiveError(f"{RECORD} does not match its checksum (edited or damaged)")
        for name, digest in record["files"].items():
            if not (record_dir / name).is_file():
                raise ArchiveError(f"{name} is missing")
            if sha256(record_dir / name) != digest:
                raise ArchiveError(f"{name} does not match its sha256 in {RECORD} (edited "
                                   "or damaged)")
        unlisted = sorted(p.name for p in record_dir.iterdir()
                          if p.name != RECORD and p.name not in record["files"])
        if unlisted:
            raise ArchiveError(f"holds {', '.join(unlisted)}, which {RECORD} does not "
                               "list (copied in?)")
        check_identity(record_dir, record)
    except (OSError, ValueError, KeyError, yaml.YAMLError, ArchiveError) as e:
        what = e if isinstance(e, ArchiveError) else f"{RECORD} cannot be read ({e})"
        raise ArchiveError(f"archive record {record_dir}: {what}: refused. Restore it from "
                           f"git (git checkout -- '{record_dir}') or remove it to compute "
                           "the run anew") from None
    return record


def _yaml_file(path):
    return yaml.safe_load(Path(path).read_text()) or {}


def check_identity(record_dir, record):
    """That a record is what it says: named by its folder, its key that of the options it
    stores, and run.yaml, summary.json's parameters, the state's options and the series'
    capsule count those options (a file copied from another run is caught). Raises
    ArchiveError (read_record() names the record)."""
    def refuse(what):
        raise ArchiveError(what)

    if (record.get("study"), record.get("name")) != (record_dir.parent.name,
                                                     record_dir.name):
        refuse(f"{RECORD} names {record.get('study')}/{record.get('name')}, another record")
    options = record["options"]
    if record["key"] != options_key(options, record["physics_version"]):
        refuse(f"its key is not that of the options {RECORD} stores (edited?)")
    if _yaml_file(record_dir / RUN_YAML) != options:
        refuse(f"{RUN_YAML} is not the options {RECORD} stores (copied from another run?)")
    others = []
    if SUMMARY in record["files"]:
        others.append((SUMMARY, json.loads((record_dir / SUMMARY).read_text())
                       .get("parameters", {})))
    if STATE in record["files"]:
        with h5py.File(record_dir / STATE, "r") as f:
            others.append((STATE, yaml.safe_load(f["options_yaml"][()].decode())))
    for name, other in others:
        differ = options_differ(other, options)
        if differ:
            refuse(f"{name} is of another run than {RUN_YAML} ({differ})")
    with h5py.File(record_dir / SERIES, "r") as f:
        capsules = int(f.attrs.get("num_capsules", 1))
    if capsules != int(flat_options(options).get("capsules", 1)):
        refuse(f"{SERIES} holds {capsules} capsules, {RUN_YAML} says "
               f"{flat_options(options).get('capsules')}")


def reached(run_dir):
    """How far a run folder got: (finished, t) with t the checkpoint's time, or the end
    of a finished run; None for a folder without a run. A finished folder must hold its
    options and series too. Raises ArchiveError naming a folder that cannot be read."""
    run_dir = Path(run_dir)
    try:
        if (run_dir / SUMMARY).exists():  # its t_end: the last row (a stop's time)
            missing = [n for n in (RUN_YAML, SERIES) if not (run_dir / n).is_file()]
            if missing:
                raise ValueError(f"finished, but {', '.join(missing)} missing")
            return True, float(json.loads((run_dir / SUMMARY).read_text())["t_end"] or 0)
        if (run_dir / CHECKPOINT).exists():
            return False, _checkpoint_time(run_dir / CHECKPOINT)
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise ArchiveError(f"run folder {run_dir} is damaged ({type(e).__name__}: {e}): "
                           f"remove it (rm -r '{run_dir}') to restore or compute the run "
                           "anew")
    return None


def folder_options(run_dir):
    """The resolved options of a run folder (its run.yaml), or None without one."""
    path = Path(run_dir) / RUN_YAML
    return _yaml_file(path) if path.is_file() else None


def folder_version(run_dir):
    """The physics version a run folder was made with: its record's, if restored, else
    that of its last segment (None where neither says: made before they did)."""
    run_dir = Path(run_dir)
    if (run_dir / RESTORED).is_file():
        return json.loads((run_dir / RESTORED).read_text())["physics_version"]
    if (run_dir / SEGMENTS).is_file():
        segments = json.loads((run_dir / SEGMENTS).read_text())
        if segments and segments[-1].get("physics_version"):
            return segments[-1]["physics_version"]
    return None


def check_length(run_dir, t_end):
    """That a finished run folder was run to `t_end`, its configuration's (run.yaml's
    t_end: what was asked, not where a stop ended it). t_end is no part of a run's key, and
    a finished folder is never run again, so a configuration that raised or lowered it
    would otherwise take the folder's series as its run. Raises ArchiveError naming the
    folder, both ends and what to do."""
    run_dir = Path(run_dir)
    got = folder_options(run_dir) if (run_dir / SUMMARY).exists() else None
    if got is None:
        return  # none, or unfinished: its next job resumes it to t_end
    asked = float(flat_options(got)["t_end"])
    if math.isclose(asked, float(t_end)):
        return
    extend = (f"; or, to continue it from its checkpoint, its {SUMMARY}"
              if (run_dir / CHECKPOINT).exists() else "")
    raise ArchiveError(f"run folder {run_dir} was run to t_end {asked:g}, this "
                       f"configuration's is {float(t_end):g}: remove it (rm -r "
                       f"'{run_dir}') to restore or compute the run anew{extend}")


def check_folder(run_dir, options):
    """That a run folder holds the run of these resolved options (its run.yaml), of this
    physics version, and, where it was restored from a record, every file as it was
    restored. Raises ArchiveError naming the folder and what to do."""
    run_dir = Path(run_dir)
    hint = f"remove it (rm -r '{run_dir}') to restore or compute the run anew"
    got = folder_options(run_dir)
    if got is None:
        return
    differ = options_differ(got, options)
    if differ:
        raise ArchiveError(f"run folder {run_dir} holds another run than this "
                           f"configuration's ({differ}): {hint}")
    version = folder_version(run_dir)
    if version is not None and version != physics_version():
        raise ArchiveError(f"run folder {run_dir} was made by physics version {version}, "
                           f"this solver's is {physics_version()}: {hint}")
    if (run_dir / RESTORED).is_file():
        files = json.loads((run_dir / RESTORED).read_text())["files"]
        for name, digest in files.items():
            if not (run_dir / name).is_file() or (
                    name != SEGMENTS and sha256(run_dir / name) != digest):
                raise ArchiveError(f"run folder {run_dir}: {name} is not as restored "
                                   f"from the archive (missing or changed): {hint}")


def _take_segments(run_dir, summary, t):
    """The segments of a run folder (segments.json), or, for a run made outside the
    job, its last invocation as summary.json gives it."""
    segments_file = run_dir / SEGMENTS
    segments = json.loads(segments_file.read_text()) if segments_file.exists() else []
    if not segments and summary:
        segments = [{"t_from": None, "t_to": t, "cpu_seconds": summary.get("cpu_seconds"),
                     "wall_seconds": summary.get("wall_seconds"),
                     "threads": summary.get("threads"), "machine": None,
                     "commit": None, "date": None}]
    return segments


def collect(run_dir, record_dir, options, final_state=False):
    """Records the run folder in the archive, as the run of the resolved `options` (the
    configuration's), replacing an older record of the same key (a record of it that
    reached as far is kept). final_state: a finished run keeps its last checkpoint as its
    state (a dilute run: figure 1 reads its capsule). Refused (ArchiveError, nothing
    written) for a folder that holds another run, and where the record holds another
    physics version or other options: that record stays as it is. Returns the record."""
    run_dir, record_dir = Path(run_dir), Path(record_dir)
    state = reached(run_dir)
    if state is None:
        raise ArchiveError(f"{run_dir}: no run to record (no summary.json, no checkpoint)")
    check_folder(run_dir, options)
    finished, t = state
    key = options_key(options, physics_version())
    record_dir.parent.mkdir(parents=True, exist_ok=True)
    with locked(record_dir.parent.parent):
        previous = read_record(record_dir) if (record_dir / RECORD).exists() else None
        if previous and previous["key"] != key:
            why = (f"physics version {previous['physics_version']}"
                   if previous["physics_version"] != physics_version() else
                   f"other options: {options_differ(previous['options'], options)}")
            raise ArchiveError(f"archive record {record_dir} holds another run ({why}): "
                               f"kept as it is, {run_dir} is not recorded. To record it "
                               f"in its place, remove the record (git rm -r '{record_dir}')")
        if previous and previous["t_reached"] >= t:
            return previous
        return _write_record(run_dir, record_dir, key, previous, finished, t, final_state)


def _write_record(run_dir, record_dir, key, previous, finished, t, final_state):
    tmp = _new_folder(record_dir)
    try:
        shutil.copyfile(run_dir / RUN_YAML, tmp / RUN_YAML)
        compact_series(run_dir / SERIES, tmp / SERIES)
        state_time = None
        if finished:
            shutil.copyfile(run_dir / SUMMARY, tmp / SUMMARY)
            kept = previous["state_time"] if previous else None
            if not final_state and kept is not None and kept < t:
                shutil.copyfile(record_dir / STATE, tmp / STATE)  # the last segment's start
                state_time = kept
            elif final_state or previous:
                # With a previous record but none of its state: a longer run of a record
                # that kept none (one segment, t_end since raised) computed its start
                # again, and its progress was no record's until it passed the old end, so
                # the start of its last segment was never kept. Its end is, lest the next
                # raise compute it all a third time.
                shutil.copyfile(run_dir / CHECKPOINT, tmp / STATE)
                state_time = _checkpoint_time(run_dir / CHECKPOINT)
        else:
            shutil.copyfile(run_dir / CHECKPOINT, tmp / STATE)
            state_time = t
        snapshot = _last_snapshot(run_dir)
        if snapshot is not None:
            shutil.copyfile(snapshot, tmp / snapshot.name)
        summary = json.loads((run_dir / SUMMARY).read_text()) if finished else {}
        segments = _take_segments(run_dir, summary, t)
        options = _yaml_file(run_dir / RUN_YAML)
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
        _replace(tmp, record_dir)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return record


def _restore_files(record_dir, run_dir, record, full):
    """Writes a record's files into the new folder run_dir, only those it lists; returns
    {file: sha256} of what was written."""
    run_dir.mkdir(parents=True, exist_ok=True)
    listed = record["files"]
    shutil.copyfile(record_dir / RUN_YAML, run_dir / RUN_YAML)
    widen_series(record_dir / SERIES, run_dir / SERIES)
    if record["state_time"] is not None:
        shutil.copyfile(record_dir / STATE, run_dir / CHECKPOINT)
    for name in sorted(n for n in listed if n.startswith("snapshot_")):
        (run_dir / "snapshots").mkdir(exist_ok=True)
        shutil.copyfile(record_dir / name, run_dir / "snapshots" / name)
    (run_dir / SEGMENTS).write_text(json.dumps(record["segments"], indent=1) + "\n")
    if full:
        shutil.copyfile(record_dir / SUMMARY, run_dir / SUMMARY)
    if not full:  # the run goes on in the folder: its files change
        return {}
    return {str(p.relative_to(run_dir)): sha256(p) for p in sorted(run_dir.rglob("*"))
            if p.is_file()}


def restore(record_dir, run_dir, record, full, marker_name=None):
    """Writes a record into a run folder, whole and at once (a temporary folder renamed
    into place): everything a finished run's readers need when `full` (summary.json
    included), else the time series and the state to continue from (as checkpoint.h5),
    with the marker file `marker_name` of the last segment it covers. Only the files the
    record lists; restored.json says what was restored."""
    record_dir, run_dir = Path(record_dir), Path(run_dir)
    tmp = _new_folder(run_dir)
    try:
        files = _restore_files(record_dir, tmp, record, full)
        if marker_name:
            (tmp / marker_name).write_text(json.dumps({"t": record["state_time"]}) + "\n")
        (tmp / RESTORED).write_text(json.dumps(
            {"record": str(record_dir), "key": record["key"],
             "physics_version": record["physics_version"], "files": files},
            indent=1, sort_keys=True) + "\n")
        _replace(tmp, run_dir)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def marker(run_dir, k):
    """The file that says segment k of a run is done (the output of its job)."""
    return Path(run_dir) / f"segment{k}.done"


def usable(record, options):
    """How a checked record serves the run of the resolved `options`: "full", "partial"
    (a state to continue from), or why not: "stale" (another physics version),
    "changed" (other options), None (it reaches no further than the start)."""
    if record["physics_version"] != physics_version():
        return "stale"
    if record["key"] != options_key(options, physics_version()):
        return "changed"
    flat = flat_options(options)
    if (record["finished"] and float(record["t_end"]) == float(flat["t_end"])
            and float(record["t_avg_start"]) == float(flat["t_avg_start"])):
        return "full"
    if record["state_time"] is not None and record["state_time"] < float(flat["t_end"]):
        return "partial"
    return None


def restore_run(record_dir, run_dir, options, pause_at=None, marker_name=None):
    """The workflow's restore job: under the archive's lock, checks the record (whole, and
    that it is the run of `options`) and restores it into run_dir: whole, or (pause_at)
    to continue from its state, which must reach pause_at, with the segment's marker.
    Nothing is done where run_dir already holds the run as far (another invocation
    restored it). Raises ArchiveError naming the record."""
    record_dir, run_dir = Path(record_dir), Path(run_dir)
    with locked(record_dir.parent.parent):
        record = read_record(record_dir)
        use = usable(record, options)
        want = "full" if pause_at is None else "partial"
        if use != want or (pause_at is not None and record["state_time"] < pause_at):
            raise ArchiveError(f"archive record {record_dir} cannot be restored as the "
                               f"{'whole run' if want == 'full' else 'start'} of {run_dir} "
                               f"({use or 'it reaches no further'}): run snakemake again")
        local = reached(run_dir)
        if local is not None:
            check_folder(run_dir, options)
            if local[0] or (pause_at is not None and local[1] >= record["state_time"]):
                if marker_name and not (run_dir / marker_name).exists():
                    (run_dir / marker_name).write_text(json.dumps({"t": local[1]}) + "\n")
                return False
        restore(record_dir, run_dir, record, full=pause_at is None, marker_name=marker_name)
        return True


def orphans(archive_root):
    """The folders of an archive (<study>/<name>, and leftovers of an interrupted
    recording) that hold no record.json: no record's."""
    root = Path(archive_root)
    return sorted(p for study in root.iterdir() if study.is_dir()
                  for p in study.iterdir() if not (p / RECORD).is_file()) \
        if root.is_dir() else []


def plan(specs, archive_root, options_of, segment_ends, workdir="."):
    """What the archive does for each run (RunSpec) of a configuration, read only (a dry
    run writes nothing). options_of(spec): the run's resolved options (asked only for a
    run that has a record or a folder); segment_ends(spec): the pause times of its
    segments. Returns {"restore": {folder: record_dir}, "continue": {folder:
    (record_dir, k, t)} (restored to continue after segment k from its state at t; k 0:
    a state before the first pause), "stale": [...],
    "changed": [...], "ahead": [...] (results/ reaches further than the record: the
    run's next job records it)}. Raises ArchiveError for a damaged record, a run folder
    that holds another run, or a folder of the archive that is no record."""
    out = {"restore": {}, "continue": {}, "stale": [], "changed": [], "ahead": []}
    empty = orphans(archive_root)
    if empty:
        raise ArchiveError(f"archive {archive_root}: {', '.join(map(str, empty))} "
                           f"hold{'s' if len(empty) == 1 else ''} no {RECORD}, so no "
                           "record: restore it from git (git checkout -- <folder>) or "
                           "remove it")
    foreign = []  # run folders of other runs: all named at once
    for spec in specs:
        run_dir = Path(workdir) / spec.folder
        record_dir = spec.record(archive_root)
        local = reached(run_dir)
        if local is None and not (record_dir / RECORD).exists():
            continue
        options = options_of(spec)
        if local is not None:
            try:
                check_folder(run_dir, options)
            except ArchiveError as e:
                foreign.append((spec.folder, e))
                continue
        if not (record_dir / RECORD).exists():
            if local is not None and (local[0] or local[1] > 0):
                out["ahead"].append(spec.folder)
            continue
        record = read_record(record_dir)
        use = usable(record, options)
        if use in ("stale", "changed"):
            out[use].append(str(record_dir))
        elif use == "full" and (local is None or not local[0]):
            out["restore"][spec.folder] = record_dir
        elif use == "partial" and (local is None or (not local[0] and
                                                     local[1] < record["state_time"])):
            ends = segment_ends(spec)
            done = [k for k, t in enumerate(ends[:-1], 1) if t <= record["state_time"]]
            # A state before the first pause (a finished run of one segment whose t_end
            # was raised, a run stopped within its first segment): continued from there,
            # "after segment 0", rather than computed again from the start.
            if done or record["state_time"] > 0:
                out["continue"][spec.folder] = (record_dir, done[-1] if done else 0,
                                                record["state_time"])
        elif local is not None and (local[0] or local[1] > record["t_reached"]) \
                and use != "full":
            out["ahead"].append(spec.folder)
    if foreign:
        others = [folder for folder, _ in foreign[1:]]
        more = (f"; and {len(others)} more alike: {', '.join(others[:4])}"
                f"{', ...' if len(others) > 4 else ''}") if others else ""
        raise ArchiveError(f"{foreign[0][1]}{more}")
    return out


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
        done = subprocess.run(resume_command(capsim, run_dir, {
            "t_end": t_end, "t_avg_start": record["state_time"], "threads": threads}, "-q"),
            capture_output=True, text=True)
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
    if args.command == "verify":
        for path in args.paths:
            for folder in orphans(path) if not (Path(path) / RECORD).exists() else []:
                print(f"archive {path}: {folder} holds no {RECORD}, so no record: restore "
                      "it from git (git checkout -- <folder>) or remove it",
                      file=sys.stderr)
                bad += 1
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

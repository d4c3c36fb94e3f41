"""One capsim run, or one segment of it, as a workflow job: the command of the run rules.

    python -m pipeline.job --capsim CAPSIM --log LOG --spec JSON [--threads N]
        [--pause-at T --segment K] [--archive DIR [--restore]]
    python -m pipeline.job --capsim CAPSIM --log LOG --archive DIR --restore --specs JSON

The job receives the run itself, a pipeline.run_spec.RunSpec as RunSpec.to_json() writes
it (--spec; --specs a JSON list of them), and derives all else from it as the workflow
does: its folder, its capsim command (RunSpec.command()), its archive record
(RunSpec.record()), its options as capsim resolves them and whether an early stop is a
result (RunSpec.stop_is_result). Nothing is parsed back from a name or from words.

A folder that holds a checkpoint (a run that was killed, a segment that paused, a run
restored from the archive, one whose t_end was raised) is continued with `capsim run
--resume RUN_DIR` and the keys capsim lets change on resume (t_end, t_avg_start,
threads, the configuration's backend); otherwise the run starts afresh with all its
keys. With --pause-at the job is segment K of the run: capsim stops at its first
checkpoint at or after T (`capsim run --pause-at`), the job writes the segment's marker
(pipeline.archive.marker()), and the next segment resumes it to the last bit; a folder
whose checkpoint is already at T (restored from the archive) runs nothing. Either way:

- capsim's output is appended to LOG after one line that says what this attempt does
  (snakemake removes a job's old log before it starts the job, so there LOG holds the
  latest attempt);
- while capsim runs, LOG is locked (an exclusive flock, held by capsim itself through its
  output): a second job for the same run, from a second snakemake started after
  `--unlock`, is refused instead of writing the same folder;
- capsim's OpenMP threads sleep rather than spin while they wait (OMP_WAIT_POLICY
  passive, unless the environment sets it): as fast alone on the machine, and far faster
  when other jobs share its cores (docs/performance.md);
- each attempt appends its provenance to RUN_DIR/segments.json (strain covered, CPU and
  wall seconds, threads, machine, date, commit, physics version, how it ended), a failed
  or killed one too (its CPU time was spent: the record counts it), and with --archive
  the folder is recorded in the results archive (pipeline.archive) at once, as the run
  of the spec's options (resolved by `capsim params --json`): a segment computed is a
  segment kept. A folder that holds another run is not recorded, and a record of
  another run is never replaced: the job says so and what to do, and succeeds (the run
  is in RUN_DIR);
- with --restore the job computes nothing: it restores the record into RUN_DIR (the
  whole run, or with --pause-at its state and the segment's marker), checked against
  the spec's options (pipeline.archive.restore_run); with --specs, each run of a list,
  whole (one job restores every finished run: a job per run cost a process start each);
- a failure ends with one line on stderr and in LOG naming the run, how capsim ended
  (its exit status, or the signal that killed it), its error message and LOG.

Exit status 3 (capsules in contact, numerical failure: summary.json says how the run
`ended`) is a success where the spec says an early stop is a result (every run but the
dilute study's: RunSpec.stop_is_result) and a failure otherwise. Any other non-zero
status is a failure; the job's own status is then capsim's (128 + N for signal N).

failure_report(snakemake_logs), which the Snakefile's onerror handler prints, lists at the
end of a failed snakemake the jobs that failed in it (with --keep-going they are far
apart in its output): a capsim run by the line above, another job by its rule, output
and log.
"""

import argparse
import datetime
import fcntl
import json
import os
import platform
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py

from pipeline import archive
from pipeline.run_spec import ROOT, RunSpec, physics_version

STOPPED = 3  # capsim: the run stopped early (contact, numerical failure)
START = "job: start"  # the first line of each attempt in the log
FAILED = "job: run "  # the last line of a failed one


def checkpoint_time(run_dir):
    """gammadot t of the run's checkpoint (None without one)."""
    path = Path(run_dir) / "checkpoint.h5"
    if not path.exists():
        return None
    with h5py.File(path, "r") as f:
        return float(f["time"][()])


def stopped(run_dir):
    """Whether the run stopped early (summary.json with `ended` other than t_end)."""
    path = Path(run_dir) / "summary.json"
    return path.exists() and json.loads(path.read_text()).get("ended") != "t_end"


def git_commit():
    """The repository's commit, with "-dirty" when tracked files differ from it ("" when
    git cannot tell)."""
    def git(*args):
        return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True,
                              text=True, check=False)
    head = git("rev-parse", "HEAD")
    if head.returncode != 0:
        return ""
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", "solver").stdout
    return head.stdout.strip() + ("-dirty" if dirty.strip() else "")


def machine():
    """The machine in a few words: host, CPU model, cores."""
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{platform.node()}: {model}, {os.cpu_count()} cores"


def record_segment(run_dir, t_from, cpu_seconds, wall_seconds, threads, ended):
    """Appends one attempt's provenance to RUN_DIR/segments.json (`ended`: how capsim
    ended, how_it_ended())."""
    path = Path(run_dir) / "segments.json"
    if not Path(run_dir).is_dir():
        return
    segments = json.loads(path.read_text()) if path.exists() else []
    segments.append({"t_from": t_from, "t_to": checkpoint_time(run_dir),
                     "cpu_seconds": round(cpu_seconds, 2),
                     "wall_seconds": round(wall_seconds, 2), "threads": threads,
                     "machine": machine(), "commit": git_commit(),
                     "date": datetime.datetime.now().isoformat(timespec="seconds"),
                     "physics_version": physics_version(), "ended": ended})
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(segments, indent=1) + "\n")
    tmp.replace(path)


def how_it_ended(returncode):
    """capsim's exit status in words: 'exit status 2' or 'killed by signal 9 (SIGKILL)'."""
    if returncode < 0:
        try:
            name = signal.Signals(-returncode).name
        except ValueError:
            name = "unknown signal"
        return f"killed by signal {-returncode} ({name})"
    return f"exit status {returncode}"


def last_message(log, offset):
    """The last non-empty line that capsim wrote to LOG after OFFSET ('' if none)."""
    with open(log, "rb") as f:
        f.seek(offset)
        lines = [line.strip() for line in f.read().decode(errors="replace").splitlines()]
    lines = [line for line in lines if line]
    return lines[-1] if lines else ""


def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


class Terminated(Exception):
    """The job was told to stop (SIGTERM, SIGINT): capsim is killed, the attempt kept."""


def _terminate(signum, frame):
    raise Terminated(signal.Signals(signum).name)


def _job_environment():
    """The environment of capsim: this one, with OMP_WAIT_POLICY passive by default."""
    return {"OMP_WAIT_POLICY": "passive", **os.environ}


def run_job(capsim, spec, log, threads, pause_at=None):
    """Runs (or resumes) one capsim run (a RunSpec), or its segment to PAUSE_AT, with its
    output appended to LOG; returns the job's exit status (0 for success)."""
    run_dir = spec.folder
    cmd, resumed = spec.command(capsim, threads, pause_at)
    Path(log).parent.mkdir(parents=True, exist_ok=True)
    with open(log, "ab") as out:
        try:
            fcntl.flock(out.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            message = (f"run {run_dir} is already running (its log {log} is locked by "
                       "another job): not started a second time")
            print(f"job: {message}", file=sys.stderr)
            return 1
        now = datetime.datetime.now().isoformat(timespec="seconds")
        what = "resuming from its checkpoint" if resumed else "starting afresh"
        out.write(f"{START} {now}: {run_dir}: {what}: {' '.join(cmd)}\n".encode())
        out.flush()
        offset = out.tell()
        t_from = checkpoint_time(run_dir) or 0.0
        cpu_before, wall_before = _children_cpu(), time.monotonic()
        # capsim writes to the locked file itself, so the lock lasts as long as capsim,
        # even if this process is killed first. A job told to stop kills capsim (run()
        # does on any exception) and still records the attempt's CPU time.
        returncode = -signal.SIGTERM
        previous = [signal.signal(s, _terminate) for s in (signal.SIGTERM, signal.SIGINT)]
        try:
            returncode = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT,
                                        env=_job_environment()).returncode
        except Terminated:
            pass  # reported below as the signal that stopped the job
        finally:
            for s, handler in zip((signal.SIGTERM, signal.SIGINT), previous):
                signal.signal(s, handler)
            record_segment(run_dir, t_from, _children_cpu() - cpu_before,
                           time.monotonic() - wall_before, threads,
                           how_it_ended(returncode))
        summary = Path(run_dir) / "summary.json"
        if returncode == 0:
            return 0
        if returncode == STOPPED and summary.exists() and spec.stop_is_result:
            print(f"job: {run_dir} stopped early (see 'ended' in {summary}): {log}",
                  file=sys.stderr)
            return 0
        message = last_message(log, offset) or "no message (see the log)"
        if returncode == STOPPED:
            kept = ("capsim stopped it early: the next snakemake resumes it to the same "
                    "stop; delete its folder to start it again")
        elif (Path(run_dir) / "checkpoint.h5").exists():
            kept = "its checkpoint is kept: the next snakemake resumes it"
        else:
            kept = "no checkpoint was written"
        line = (f"{FAILED}{run_dir} FAILED ({how_it_ended(returncode)}): {message}; "
                f"{kept}; log: {log}")
        out.write((line + "\n").encode())
    print(line, file=sys.stderr)
    return 128 - returncode if returncode < 0 else returncode


def failed_jobs(snakemake_log):
    """The jobs that failed in one snakemake invocation, read from its own log file
    (.snakemake/log/*.snakemake.log): a list of dicts with the rule and the job's
    `wildcards`, `output` and `log` as snakemake printed them ('' where absent)."""
    jobs, job = [], None
    for line in Path(snakemake_log).read_text(errors="replace").splitlines():
        if line.startswith("Error in rule "):
            job = {"rule": line[len("Error in rule "):].rstrip(":"), "wildcards": "",
                   "output": "", "log": ""}
            jobs.append(job)
        elif job is not None and line.startswith("    ") and ": " in line:
            key, value = line.strip().split(": ", 1)
            if key in ("wildcards", "output", "log") and not job[key]:
                job[key] = value.split(" (check log file(s)")[0]
        elif job is not None and not line.startswith("    "):
            job = None
    return jobs


def failure_report(snakemake_logs):
    """The text that names every failed job of a snakemake invocation: for a capsim run
    the FAILED line of its log, for another job its rule, output and log. snakemake_logs:
    the path of the invocation's log, or a list of them (what onerror is given)."""
    if isinstance(snakemake_logs, (str, os.PathLike)):
        snakemake_logs = [snakemake_logs]
    jobs = [job for path in snakemake_logs if Path(path).is_file()
            for job in failed_jobs(path)]
    if not jobs:
        return ""
    lines = [f"Failed jobs of this snakemake ({len(jobs)}); run it again to redo them "
             "(a killed run resumes from its checkpoint):"]
    for job in jobs:
        failed = []
        if job["log"] and Path(job["log"]).is_file():
            attempts = Path(job["log"]).read_text(errors="replace").split(START)
            failed = [line for line in attempts[-1].splitlines() if line.startswith(FAILED)]
        if failed:  # names the run, how capsim ended, its message and the log
            lines.append("  " + failed[-1][len("job: "):])
        else:
            lines.append(f"  rule {job['rule']} ({job['wildcards'] or job['output']}): "
                         f"log {job['log'] or '-'}")
    return "\n".join(lines)


def _say(log, line):
    """One line on stderr and in the job's log."""
    print(line, file=sys.stderr)
    Path(log).parent.mkdir(parents=True, exist_ok=True)
    with open(log, "a") as out:
        out.write(line + "\n")


def record_run(spec, capsim, archive_root):
    """Records the run's folder in the archive, as the run of its spec's options as capsim
    resolves them. Raises pipeline.archive.ArchiveError (another run in the folder or in
    the record) or OSError (an archive that cannot be written)."""
    archive.collect(spec.folder, spec.record(archive_root), spec.resolved_options(capsim),
                    final_state=spec.dilute)


def record_job(args, spec):
    """Records the run folder in the archive; where it cannot be, says why and what to
    do, and the job still succeeds: the run is in its folder."""
    try:
        record_run(spec, args.capsim, args.archive)
    except (archive.ArchiveError, OSError) as e:
        _say(args.log, f"job: {spec.folder} NOT RECORDED in the archive: {e}")


def restore_job(args, specs):
    """The job of the restore rules: each run's record into its folder (whole, or with
    --pause-at to continue from its state, with the segment's marker); exit 1 where one
    cannot be, the record named."""
    status = 0
    for spec in specs:
        record = spec.record(args.archive)
        marker = (archive.marker(spec.folder, args.segment).name
                  if args.segment is not None else None)
        try:
            done = archive.restore_run(record, spec.folder,
                                       spec.resolved_options(args.capsim), args.pause_at,
                                       marker)
        except (archive.ArchiveError, OSError) as e:
            _say(args.log, f"job: {spec.folder} not restored: {e}")
            status = 1
            continue
        _say(args.log, f"job: {spec.folder} " + ("restored from " if done else
                                                 "already holds ") + str(record))
    return status


def arguments(argv):
    """The job's command line, checked."""
    ap = argparse.ArgumentParser(description="Run or resume one capsim run as a job.")
    ap.add_argument("--capsim", required=True, help="the capsim executable")
    ap.add_argument("--log", required=True, help="the job's log, appended to")
    ap.add_argument("--spec", type=RunSpec.from_json, metavar="JSON",
                    help="the run (RunSpec.to_json())")
    ap.add_argument("--specs", type=lambda text: [RunSpec.from_json(s)
                                                  for s in json.loads(text)],
                    metavar="JSON", help="with --restore: restore each run of a JSON list "
                    "of specs, whole, instead of --spec")
    ap.add_argument("--threads", type=int, default=1, help="capsim's threads")
    ap.add_argument("--pause-at", type=float, metavar="T",
                    help="run one segment: to the first checkpoint at or after strain T")
    ap.add_argument("--segment", type=int, metavar="K",
                    help="with --pause-at: the segment's number (its marker, the output "
                    "of a segment job)")
    ap.add_argument("--archive", help="the results archive to record the folder in")
    ap.add_argument("--restore", action="store_true",
                    help="with --archive: restore the record into the folder, run nothing")
    args = ap.parse_args(argv)
    if (args.spec is None) == (args.specs is None):
        ap.error("give --spec, or --specs with --restore")
    if args.specs is not None and not args.restore:
        ap.error("--specs needs --restore")
    if args.restore and not args.archive:
        ap.error("--restore needs --archive")
    if (args.pause_at is None) != (args.segment is None):
        ap.error("--pause-at and --segment go together")
    return args


def main(argv=None):
    args = arguments(sys.argv[1:] if argv is None else list(argv))
    if args.restore:
        return restore_job(args, args.specs or [args.spec])
    spec = args.spec
    reached = checkpoint_time(spec.folder)
    if args.pause_at is not None and (stopped(spec.folder) or
                                      (reached is not None and reached >= args.pause_at)):
        status = 0  # restored past this segment's end, or stopped early before it
    else:
        status = run_job(args.capsim, spec, args.log, args.threads, args.pause_at)
    if status == 0 and args.archive:
        record_job(args, spec)
    if status == 0 and args.segment is not None:
        archive.marker(spec.folder, args.segment).write_text(
            json.dumps({"t": checkpoint_time(spec.folder)}) + "\n")
    return status


if __name__ == "__main__":
    sys.exit(main())

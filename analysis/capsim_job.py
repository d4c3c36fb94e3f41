"""One capsim run as a workflow job: the command of the workflow's run rules.

    python -m analysis.capsim_job --capsim CAPSIM --dir RUN_DIR --log LOG
        [--resume-set KEY=VALUE ...] [--stopped-ok] -- --set KEY=VALUE ...

A folder that holds a checkpoint (a run that was killed, or one whose t_end was raised)
is continued with `capsim run --resume RUN_DIR` and the --resume-set keys (those capsim
lets change on resume: t_end, threads, ...); otherwise the run starts afresh with the keys
after `--`. Either way:

- capsim's output is appended to LOG after one line that says what this attempt does
  (snakemake removes a job's old log before it starts the job, so there LOG holds the
  latest attempt);
- while capsim runs, LOG is locked (an exclusive flock, held by capsim itself through its
  output): a second job for the same run, from a second snakemake started after
  `--unlock`, is refused instead of writing the same folder;
- capsim's OpenMP threads sleep rather than spin while they wait (OMP_WAIT_POLICY
  passive, unless the environment sets it): as fast alone on the machine, and far faster
  when other jobs share its cores (docs/performance.md);
- a failure ends with one line on stderr and in LOG naming the run, how capsim ended
  (its exit status, or the signal that killed it), its error message and LOG.

Exit status 3 (capsules in contact, numerical failure: summary.json says how the run
`ended`) is a success with --stopped-ok (the suspension runs, whose tables and figures
name such runs) and a failure without it. Any other non-zero status is a failure; the
job's own status is then capsim's (128 + N for signal N).

failure_report(snakemake_logs), which the Snakefile's onerror handler prints, lists at the
end of a failed snakemake the jobs that failed in it (with --keep-going they are far
apart in its output): a capsim run by the line above, another job by its rule, output
and log.
"""

import argparse
import datetime
import fcntl
import os
import signal
import subprocess
import sys
from pathlib import Path

STOPPED = 3  # capsim: the run stopped early (contact, numerical failure)
START = "capsim_job: start"  # the first line of each attempt in the log
FAILED = "capsim_job: run "  # the last line of a failed one


def option_value(value):
    """A configuration value as capsim's `--set key=value` spells it: YAML's booleans as
    true/false (capsim refuses Python's True), the rest as str() writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def set_options(options):
    """`--set key=value` for each item of a mapping, in its order."""
    return " ".join(f"--set {k}={option_value(v)}" for k, v in options.items())


def capsim_command(capsim, run_dir, fresh_args, resume_args):
    """The capsim command line for RUN_DIR, and whether it resumes."""
    if (Path(run_dir) / "checkpoint.h5").exists():
        return [capsim, "run", "-q", "--resume", str(run_dir), *resume_args], True
    return [capsim, "run", "-q", *fresh_args, "-o", str(run_dir)], False


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


def _job_environment():
    """The environment of capsim: this one, with OMP_WAIT_POLICY passive by default."""
    return {"OMP_WAIT_POLICY": "passive", **os.environ}


def run_job(capsim, run_dir, log, fresh_args, resume_args, stopped_ok=False):
    """Runs (or resumes) one capsim run with its output appended to LOG; returns the
    job's exit status (0 for success)."""
    cmd, resumed = capsim_command(capsim, run_dir, fresh_args, resume_args)
    Path(log).parent.mkdir(parents=True, exist_ok=True)
    with open(log, "ab") as out:
        try:
            fcntl.flock(out.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            message = (f"run {run_dir} is already running (its log {log} is locked by "
                       "another job): not started a second time")
            print(f"capsim_job: {message}", file=sys.stderr)
            return 1
        now = datetime.datetime.now().isoformat(timespec="seconds")
        what = "resuming from its checkpoint" if resumed else "starting afresh"
        out.write(f"{START} {now}: {run_dir}: {what}: {' '.join(cmd)}\n".encode())
        out.flush()
        offset = out.tell()
        # capsim writes to the locked file itself, so the lock lasts as long as capsim,
        # even if this process is killed first.
        returncode = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT,
                                    env=_job_environment()).returncode
        summary = Path(run_dir) / "summary.json"
        if returncode == 0:
            return 0
        if returncode == STOPPED and summary.exists() and stopped_ok:
            print(f"capsim_job: {run_dir} stopped early (see 'ended' in {summary}): {log}",
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
            lines.append("  " + failed[-1][len("capsim_job: "):])
        else:
            lines.append(f"  rule {job['rule']} ({job['wildcards'] or job['output']}): "
                         f"log {job['log'] or '-'}")
    return "\n".join(lines)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    fresh = []
    if "--" in argv:
        cut = argv.index("--")
        argv, fresh = argv[:cut], argv[cut + 1:]
    ap = argparse.ArgumentParser(description="Run or resume one capsim run as a job.")
    ap.add_argument("--capsim", required=True, help="the capsim executable")
    ap.add_argument("--dir", required=True, help="the run folder (capsim -o)")
    ap.add_argument("--log", required=True, help="the job's log, appended to")
    ap.add_argument("--resume-set", action="append", default=[], metavar="KEY=VALUE",
                    help="a key given on resume (t_end, threads, ...)")
    ap.add_argument("--stopped-ok", action="store_true",
                    help="a run that stopped early (exit 3, summary.json written) succeeds")
    args = ap.parse_args(argv)
    resume = [a for kv in args.resume_set for a in ("--set", kv)]
    return run_job(args.capsim, args.dir, args.log, fresh, resume, args.stopped_ok)


if __name__ == "__main__":
    sys.exit(main())

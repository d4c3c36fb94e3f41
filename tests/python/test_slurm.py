"""The cluster path against a real scheduler: a one-node SLURM started on this machine
(tests/python/one_node_slurm.py) runs the workflow through the SLURM profile
(profiles/slurm, snakemake-executor-plugin-slurm), and its outputs are held against the
local executor's of the same targets:

- the ci configuration (config/ci.yaml), `all check`: every run is a job of its own with
  the resources the profile and the configuration state (CPUs, memory, time limit, read
  back from slurmctld with `scontrol show job`), the tables, figures and the check are
  made where snakemake runs (the Snakefile's localrules), and
  every run's output and every figure's and table's data equal the local executor's to
  the last bit;
- chained segments under a time limit: one run in two segments (segments.strain 1) on
  the partition `short` (a 1-minute limit, resources.suspension_minutes 1), each segment
  a job; capsim of the second is paused (SIGSTOP) after a checkpoint within the segment,
  so that the job overruns its limit without holding a core, and the scheduler kills it
  (TIMEOUT); the profile's retry resumes it from that checkpoint in the next job, and the
  run ends equal, to the last bit, to the same run computed unsegmented and uninterrupted
  by the local executor; the run's archive record keeps its segments.

A third test, without the cluster, checks that the cost model cuts the runs of
config/paper.yaml into segments that fit a 4-hour partition (docs/workflow.md).

The local executor's ci workflow is the ci_workflow fixture (conftest.py), made once for
this file and test_workflow_ci.py before the cluster starts. The two cluster tests run at
once, the chain in the background while the ci workflow runs: the chain waits at least
a minute for the time limit, and the plugin polls SLURM less often the longer no job
ends (10 s more each time). Where SLURM is not installed, this is not root or the daemons
do not start, the test fails and says why (the daemons' logs included); scripts/setup.sh
installs the Debian packages."""

import json
import os
import re
import signal
import subprocess
import threading
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml

from one_node_slurm import SHORT_MINUTES, ClusterError, OneNodeSlurm, environment
from test_workflow_ci import CAPSIM, ROOT, SNAKEMAKE, pytestmark  # noqa: F401 (the skips)

PROFILE = ROOT / "profiles" / "slurm"
CI = ROOT / "config" / "ci.yaml"
# No accounting database here: the plugin asks squeue (sacct answers "Slurm accounting
# storage is disabled"), and polls after 1 s instead of 40 s.
PLUGIN_ARGS = ["--slurm-status-command", "squeue",
               "--slurm-init-seconds-before-status-checks", "1"]
TARGETS = ("all", "check")
CHAIN_RUN = "grid/ca0.4_phi0.2_M2_level3_seed1"
CHAIN = {  # two segments of one strain, a checkpoint every 0.1; 1 thread, 1 minute
    "grid": {"ca": [0.4], "phi": [0.2], "capsules": 2, "mesh_level": 3, "seeds": [1],
             "t_end": 2},
    "resources": {"threads": 1, "suspension_minutes": SHORT_MINUTES},
    "run_options": {"output.checkpoint_interval": 0.1},
    "segments": {"strain": 1},
}


def snakemake(workdir, *targets, configs=(), profile=None, background=False, nice=0):
    """Snakemake on the ci configuration (and `configs` over it) in `workdir`, with the
    local executor on 2 cores or the SLURM profile; returns the finished process, or the
    running one. Its output goes to workdir/snakemake.out. `nice`: its niceness, which
    the jobs it submits take too (PropagatePrioProcess)."""
    runner = ["--profile", str(profile), *PLUGIN_ARGS] if profile else ["--cores", "2"]
    cmd = [str(SNAKEMAKE), *runner, "--snakefile", str(ROOT / "Snakefile"),
           "--directory", str(workdir), "--configfile", str(CI), *map(str, configs),
           "--", *targets]
    Path(workdir).mkdir(parents=True, exist_ok=True)
    with open(Path(workdir) / "snakemake.out", "w") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, cwd=ROOT,
                                env=environment(), preexec_fn=lambda: os.nice(nice))
    return proc if background else finish(proc, workdir)


def finish(proc, workdir, timeout=900):
    """Waits for a snakemake of snakemake(); its output becomes proc.output."""
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.terminate()
        proc.wait(timeout=60)
    proc.output = (Path(workdir) / "snakemake.out").read_text(errors="replace")
    return proc


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    slurm = OneNodeSlurm(tmp_path_factory.mktemp("slurm"))
    error = None
    try:
        slurm.start()
    except (ClusterError, OSError, subprocess.SubprocessError) as e:
        error = str(e)
    if error:
        slurm.stop()
        pytest.fail(f"one-node SLURM could not start: {error}", pytrace=False)
    yield slurm
    slurm.stop()


# ---- the jobs, as slurmctld reports them ---------------------------------------------

def megabytes(text):
    number, unit = re.fullmatch(r"([\d.]+)([KMGT]?)", text).groups()
    return float(number) * {"K": 1 / 1024, "": 1, "M": 1, "G": 1024, "T": 1024**2}[unit]


def minutes(limit):
    days, _, clock = limit.rpartition("-")
    h, m, s = (int(x) for x in clock.split(":"))
    return (int(days) if days else 0) * 1440 + h * 60 + m + s / 60


def rule_and_wildcards(job):
    """The plugin names each job's rule and wildcards in its comment."""
    rule, _, wildcards = job["Comment"].removeprefix("rule_").partition("_wildcards_")
    return rule, wildcards


def jobs_in(cluster, workdir):
    """The jobs of the snakemake that worked in `workdir`, in submission order."""
    work = str(Path(workdir).resolve())
    return sorted((j for j in cluster.jobs() if j.get("WorkDir") == work),
                  key=lambda j: int(j["JobId"]))


def profile():
    return yaml.safe_load((PROFILE / "config.yaml").read_text())


def configured_resources():
    """The configuration's resources: the schema's defaults, config.yaml's, ci.yaml's."""
    schema = ROOT / "workflow" / "schemas" / "config.schema.yaml"
    props = yaml.safe_load(schema.read_text())["properties"]["resources"]["properties"]
    res = {k: v["default"] for k, v in props.items() if "default" in v}
    for path in (ROOT / "config" / "config.yaml", CI):
        res.update((yaml.safe_load(path.read_text()) or {}).get("resources", {}))
    return res


def expected_resources(rule, wildcards, res):
    """(CPUs, MB, minutes) of a job: a run's from the profile's cpus_per_task and the
    configuration's resources (dilute_* or suspension_*), any other's from the profile's
    defaults, with one CPU."""
    prof = profile()
    if rule in ("run", "run_segment"):
        kind = "dilute" if wildcards.startswith("dilute_") else "suspension"
        return (prof["set-resources"][rule]["cpus_per_task"], res[f"{kind}_mem_mb"],
                res[f"{kind}_minutes"])
    return 1, prof["default-resources"]["mem_mb"], prof["default-resources"]["runtime"]


def requested(job):
    return int(job["NumCPUs"]), megabytes(job["MinMemoryNode"]), minutes(job["TimeLimit"])


# ---- outputs, compared to the last bit -----------------------------------------------

def h5_contents(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[()])
                     if isinstance(o, h5py.Dataset) else None)
    return out


def assert_same_h5(got, want):
    a, b = h5_contents(got), h5_contents(want)
    assert a.keys() == b.keys(), got
    for name in a:
        x, y = np.asarray(a[name]), np.asarray(b[name])
        assert x.dtype == y.dtype and x.shape == y.shape, f"{got}: {name}"
        assert x.tobytes() == y.tobytes(), f"{got}: {name} differs from {want}"


def summary_values(path):
    """summary.json without what times or describes the invocation."""
    data = json.loads(Path(path).read_text())
    return {k: v for k, v in data.items() if "seconds" not in k and k != "resumed"}


def assert_same_run(got, want):
    """Every HDF5 file of a run folder (time series, checkpoint, snapshots) to the last
    bit, its resolved options and its summary's values."""
    files = sorted(p.relative_to(want) for p in want.rglob("*.h5"))
    assert files == sorted(p.relative_to(got) for p in got.rglob("*.h5")), got
    for rel in files:
        assert_same_h5(got / rel, want / rel)
    assert (got / "run.yaml").read_text() == (want / "run.yaml").read_text()
    assert summary_values(got / "summary.json") == summary_values(want / "summary.json")


def run_folders(results):
    return sorted(p.parent.relative_to(results) for p in results.glob("*/*/summary.json"))


def data_files(results):
    """The tables and figure data (every CSV) under results/."""
    return sorted(p.relative_to(results) for p in results.glob("**/*.csv"))


# ---- the chain: a segment killed at its time limit -----------------------------------

def checkpoint_time(run_dir):
    try:
        with h5py.File(run_dir / "checkpoint.h5", "r") as f:
            return float(f["time"][()])
    except (OSError, KeyError):
        return None  # not there yet, or being replaced


def capsim_pids(workdir):
    """capsim processes working in `workdir` (started there by a job)."""
    pids = []
    for proc in Path("/proc").iterdir():
        try:
            exe = (proc / "cmdline").read_bytes().split(b"\0")[0]
            if exe.endswith(b"capsim") and (proc / "cwd").resolve() == workdir.resolve():
                pids.append(int(proc.name))
        except (OSError, ValueError):
            continue
    return pids


def slurm_job_of(pid):
    """The SLURM job id a process runs in (its SLURM_JOB_ID), or None."""
    try:
        env = (Path("/proc") / str(pid) / "environ").read_bytes().split(b"\0")
    except OSError:
        return None
    ids = [v.removeprefix(b"SLURM_JOB_ID=") for v in env if v.startswith(b"SLURM_JOB_ID=")]
    return ids[0].decode() if ids else None


def pause_within_second_segment(workdir, proc, paused):
    """Pauses capsim (SIGSTOP) once it has written a checkpoint inside the second
    segment (1.15 < t < 1.8: the first pauses at its first checkpoint at or after t = 1,
    one step of about 0.06 later at most): its job then runs into the time limit without
    using a core."""
    run_dir = workdir / "results" / CHAIN_RUN
    while proc.poll() is None and not paused:
        t = checkpoint_time(run_dir)
        if t is not None and 1.15 < t < 1.8:
            for pid in capsim_pids(workdir):
                os.kill(pid, signal.SIGSTOP)
                paused.update(pid=pid, t=t, job=slurm_job_of(pid))
        time.sleep(0.02)


@pytest.fixture(scope="module")
def chain(cluster, tmp_path_factory):
    """Starts the segmented run through the profile on the partition `short` (with the
    archive), and the same run unsegmented with the local executor; yields (process,
    working directory, what was paused, the local run's process and directory)."""
    work = tmp_path_factory.mktemp("slurm_chain")
    plain = tmp_path_factory.mktemp("slurm_chain_uninterrupted")
    target = f"results/{CHAIN_RUN}/summary.json"
    unsegmented = {k: v for k, v in CHAIN.items() if k != "segments"}
    (plain / "plain.yaml").write_text(yaml.safe_dump(unsegmented))
    reference = snakemake(plain, target, configs=[plain / "plain.yaml"], background=True)
    prof = profile()
    prof["default-resources"]["slurm_partition"] = "short"
    (work / "profile").mkdir()
    (work / "profile" / "config.yaml").write_text(yaml.safe_dump(prof))
    archived = {**CHAIN, "archive": str(work / "archive")}
    (work / "chain.yaml").write_text(yaml.safe_dump(archived))
    proc = snakemake(work, target, configs=[work / "chain.yaml"], profile=work / "profile",
                     background=True)
    paused = {}
    threading.Thread(target=pause_within_second_segment, args=(work, proc, paused),
                     daemon=True).start()
    yield proc, work, paused, reference, plain
    for p in (proc, reference):
        if p.poll() is None:
            p.terminate()
            p.wait(timeout=60)


# ---- the tests -----------------------------------------------------------------------

def test_a_paper_scale_run_is_cut_into_segments_that_fit_a_partition_s_limit():
    """The example of docs/workflow.md ("On a cluster"): with a 4-hour partition,
    suspension_minutes 240 and segments.minutes 160, each segment of a grid point of
    config/paper.yaml is estimated (RunSpec.seconds_per_strain, 2 cores) to take no
    longer than 160 minutes, though all but the Ca 0.6 points take longer than the
    limit in all."""
    from pipeline import run_spec
    paper = yaml.safe_load((ROOT / "config" / "paper.yaml").read_text())
    default = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    options = {**default["run_options"], **paper.get("run_options", {})}
    grid = paper["grid"]
    longer = 0
    for ca in grid["ca"]:
        for phi in grid["phi"]:
            keys = {"ca": ca, "phi": phi, "M": grid["capsules"],
                    "level": grid["mesh_level"], "seed": 1}
            spec = run_spec.suspension("grid", keys, grid, paper["averages"]["t_start"],
                                       options)
            per_strain = spec.seconds_per_strain()
            lengths = np.diff([0.0, *spec.segment_ends(minutes=160)])
            assert max(lengths) * per_strain <= 160 * 60, spec.name
            longer += per_strain * spec.t_end > 240 * 60
    assert longer == len(grid["phi"]) * (len(grid["ca"]) - 1)


def test_the_ci_workflow_through_the_slurm_profile_equals_the_local_executor(
        cluster, chain, ci_workflow, tmp_path):
    # The local executor's outputs: the ci_workflow fixture (conftest.py), which
    # test_workflow_ci.py reads too, made before the cluster's jobs start. `chain` runs
    # in the background meanwhile, ahead of these (niceness 19): its jobs other than the
    # one it pauses must end within their 1-minute limit. Each of its jobs computes about
    # a second but starts a snakemake (~3 s of a core) beside the jobs of these: at
    # niceness 10 they leave it about a third of a core, at 19 about four fifths, and the
    # limit is then room for a machine several times slower.
    local_dir, local = ci_workflow
    assert local.returncode == 0, local.stdout[-3000:] + local.stderr[-3000:]
    slurm = snakemake(tmp_path / "slurm", *TARGETS, profile=PROFILE, nice=19)
    assert slurm.returncode == 0, slurm.output[-4000:]

    jobs = jobs_in(cluster, tmp_path / "slurm")
    assert [j["Comment"] for j in jobs if j["JobState"] != "COMPLETED"] == []
    # Only what runs capsim is a job; tables, figures and the check run where snakemake
    # runs (the Snakefile's localrules).
    assert {rule_and_wildcards(j)[0] for j in jobs} == {"run", "multipole_error"}
    res = configured_resources()
    submitted_runs = set()
    for job in jobs:
        rule, wildcards = rule_and_wildcards(job)
        assert requested(job) == expected_resources(rule, wildcards, res), job["Comment"]
        if rule == "run":
            submitted_runs.add(wildcards)
    want, got = local_dir / "results", tmp_path / "slurm" / "results"
    runs = run_folders(want)
    assert len(runs) == 16 and run_folders(got) == runs
    assert submitted_runs == {str(r).replace("/", "_") for r in runs}

    for n in range(1, 13):
        for ext in ("png", "pdf", "csv"):
            assert (got / "figures" / f"fig{n:02d}.{ext}").stat().st_size > 0
    assert "0 failed" in (got / "check" / "report.md").read_text()
    for run in runs:
        assert_same_run(got / run, want / run)
    tables = data_files(got)
    assert tables and tables == data_files(want)
    for rel in tables:
        assert (got / rel).read_bytes() == (want / rel).read_bytes(), rel
    print(f"slurm: {len(jobs)} jobs, one per run ({len(runs)}) and the multipole error's, "
          "with the CPUs, memory and time limit of profiles/slurm and the configuration; "
          f"figures 1-12 and the check made; the runs and {len(tables)} tables and figure "
          "data files equal the local executor's to the last bit")


def test_a_segment_killed_at_its_time_limit_resumes_to_the_uninterrupted_run(
        cluster, chain):
    proc, work, paused, reference, plain = chain
    proc = finish(proc, work)
    assert paused, "capsim was not paused in the second segment\n" + proc.output[-3000:]
    assert proc.returncode == 0, proc.output[-4000:]

    jobs = jobs_in(cluster, work)
    # The first segment, the second (the run's last) killed at its limit, its retry.
    states = [(rule_and_wildcards(j)[0], j["JobState"]) for j in jobs]
    run_times = [(j["JobId"], j["RunTime"]) for j in jobs]
    assert states == [("run_segment", "COMPLETED"), ("run", "TIMEOUT"),
                      ("run", "COMPLETED")], (states, run_times, paused)
    assert paused["job"] == jobs[1]["JobId"], (paused, run_times)
    for j in jobs:
        assert j["Partition"] == "short" and minutes(j["TimeLimit"]) == CHAIN["resources"]["suspension_minutes"], j["Comment"]

    run_dir = work / "results" / CHAIN_RUN
    log = (work / "results" / "logs" / f"{CHAIN_RUN}.log").read_text()
    assert "resuming from its checkpoint" in log, log
    record = json.loads((work / "archive" / CHAIN_RUN / "record.json").read_text())
    assert record["finished"]
    segments = [(s["t_from"], s["t_to"], s["ended"]) for s in record["segments"]]
    # The first segment and the retry, which started from the checkpoint the killed job
    # had written, not from the end of the first segment. The killed attempt is listed
    # between them only where its job recorded it before SLURM's signals ended it.
    assert segments[0][0] == 0 and segments[-1][1] >= CHAIN["grid"]["t_end"], segments
    assert segments[-1][0] >= paused["t"] - 1e-9 > segments[0][1], (paused, segments)
    assert len(segments) == 2 or "SIGTERM" in segments[1][2], segments

    reference = finish(reference, plain)
    assert reference.returncode == 0, reference.output[-3000:]
    assert not list((plain / "results" / "logs").rglob("*.segment*.log"))
    uninterrupted = plain / "results" / CHAIN_RUN
    assert_same_h5(run_dir / "timeseries.h5", uninterrupted / "timeseries.h5")
    assert summary_values(run_dir / "summary.json") == summary_values(
        uninterrupted / "summary.json")
    print(f"slurm: {CHAIN_RUN}: the second of its two segment jobs, paused at t = "
          f"{paused['t']:.2f}, killed at its {SHORT_MINUTES}-minute limit (TIMEOUT), resumed "
          f"in the next job from t = {segments[-1][0]:.2f}; equal to the uninterrupted run "
          "to the last bit")

"""The workflow under faults (docs/reliability.md, "The workflow under faults"), on tiny
configurations written to a temporary working directory:

- one run of a study fails with a parameter capsim rejects: with --keep-going the others
  finish, a stopped run (capsules in contact) counts as finished, and the failed run is
  named with capsim's message and its log;
- a run whose capsim is killed with SIGKILL fails its job; a second snakemake resumes it
  from its checkpoint instead of starting again;
- a second snakemake on the same working directory, started while the first runs a job,
  is refused by snakemake's lock;
- a second job for a run whose capsim is still running is refused (pipeline.job);
- a finished run whose t_end the configuration raised stops the workflow, named, and
  continues from its checkpoint once its summary is removed.

About 30 s on 2 cores. Skipped when build/capsim or snakemake is missing."""

import fcntl
import json
import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest
import yaml

from pipeline.command_line import set_arguments
from pipeline.job import run_job
from pipeline.run_spec import RunSpec
from analysis.read_run import read_timeseries
from analysis.tables import read_table

from test_workflow_ci import CAPSIM, ROOT, SNAKEMAKE, pytestmark  # noqa: F401 (the skips)

# Mesh study: level 1 and level 2 (seeds 1, 2). method patches with patch level 2 is
# refused by capsim at mesh level 1 only ("at most mesh_level"): one bad run of three.
# Grid study at level 2: with stop_distance 0.3 the capsules at phi 0.4 touch at once
# (a contact stop, exit 3), those at phi 0.05 do not.
BAD_RUN_CONFIG = {
    "averages": {"t_start": 0.1},
    "resources": {"threads": 1},
    "run_options": {"method": "patches", "ewald.patch_level": 2,
                    "suspension.stop_distance": 0.3},
    "dilute": {"ca": [0.2], "mesh_levels": [2], "t_end": 0.3, "t_avg_start": 0.1},
    "grid": {"ca": [0.2], "phi": [0.05, 0.4], "capsules": 2, "mesh_level": 2,
             "seeds": [1], "t_end": 0.3},
    "mesh": {"ca": 0.4, "phi": 0.2, "capsules": 2, "mesh_levels": [1, 2], "seeds": [1, 2],
             "t_end": 0.3},
}
BAD_RUN = "results/mesh/ca0.4_phi0.2_M2_level1_seed1"

# A dilute run of a tenth of a strain unit, for the job alone.
TINY_SPEC = RunSpec(study="dilute", ca=0.2, level=1, t_end=0.1, t_avg_start=0.0)

# One grid run long enough to be killed midway (a few seconds), checkpointed often; its
# step and Ewald tolerance pinned, so that the defaults' speed does not shorten it.
LONG_RUN_CONFIG = {
    "averages": {"t_start": 0.1},
    "resources": {"threads": 1},
    "run_options": {"output.checkpoint_interval": 0.2, "dt_safety": 0.5,
                    "ewald.tolerance": 1e-6},
    # t_end 80: about 6 s alone, so that the test finds capsim still running after its
    # first checkpoints even when the machine is loaded (at 20, 1.5 s, it sometimes ended
    # first).
    "grid": {"ca": [0.4], "phi": [0.1], "capsules": 2, "mesh_level": 1, "seeds": [1],
             "t_end": 80},
}
LONG_RUN = "results/grid/ca0.4_phi0.1_M2_level1_seed1"


def snakemake_cmd(workdir, *args):
    exe = str(SNAKEMAKE) if SNAKEMAKE.exists() else shutil.which("snakemake")
    return [exe, "--cores", "2", "--snakefile", str(ROOT / "Snakefile"), "--directory",
            str(workdir), *args, "--configfile", str(workdir / "faults.yaml")]


def snakemake(workdir, *args):
    return subprocess.run(snakemake_cmd(workdir, *args), capture_output=True, text=True,
                          timeout=300)


def write_config(workdir, config):
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "faults.yaml").write_text(yaml.safe_dump(config))


def capsim_pids(workdir):
    """The capsim processes started in `workdir` (snakemake runs its jobs there)."""
    pids = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            argv0 = (proc / "cmdline").read_bytes().split(b"\0")[0].decode()
            cwd = os.readlink(proc / "cwd")
        except OSError:
            continue
        if argv0 == str(CAPSIM) and Path(cwd) == workdir:
            pids.append(int(proc.name))
    return pids


def wait_for(condition, what, timeout=60):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


# A dilute run of a fifth of a strain unit, whose t_end the configuration then raises.
SHORT_CONFIG = {"resources": {"threads": 1},
                "dilute": {"ca": [0.2], "mesh_levels": [2], "t_end": 0.2,
                           "t_avg_start": 0.0}}
SHORT_RUN = "results/dilute/ca0.2_level2"


def test_a_finished_run_of_another_t_end_stops_the_workflow_until_told_what_to_do(
        tmp_path):
    # t_end is no part of a run's key and a finished folder is never run again: the
    # shorter run must not stand as the raised configuration's, in a dry run either.
    target = f"{SHORT_RUN}/summary.json"
    write_config(tmp_path, SHORT_CONFIG)
    first = snakemake(tmp_path, target)
    assert first.returncode == 0, first.stderr[-3000:]
    write_config(tmp_path, {**SHORT_CONFIG,
                            "dilute": {**SHORT_CONFIG["dilute"], "t_end": 0.4}})
    raised = snakemake(tmp_path, "-n", target)
    said = raised.stdout + raised.stderr  # a WorkflowError goes to stdout
    assert raised.returncode != 0
    assert (f"run folder {SHORT_RUN} was run to t_end 0.2, this configuration's is 0.4: "
            f"remove it (rm -r '{SHORT_RUN}')") in said, said[-2000:]
    assert "or, to continue it from its checkpoint, its summary.json" in said
    # Told so, the run continues from its checkpoint to the raised t_end.
    (tmp_path / SHORT_RUN / "summary.json").unlink()
    again = snakemake(tmp_path, target)
    assert again.returncode == 0, again.stderr[-3000:]
    summary = json.loads((tmp_path / SHORT_RUN / "summary.json").read_text())
    assert summary["resumed"] is True and summary["t_end"] >= 0.4


def test_run_options_reach_capsim_in_its_spelling(tmp_path):
    # A YAML boolean in run_options (membrane.wrinkling: true) is Python's True, which
    # capsim refuses: every suspension run would stop at once with exit 2.
    options = " ".join(set_arguments({"membrane.wrinkling": True, "ca": 0.2,
                                      "mesh_level": 1, "t_end": 0.01, "t_avg_start": 0,
                                      "threads": 1}))
    assert "--set membrane.wrinkling=true" in options
    proc = subprocess.run([str(CAPSIM), "run", "-q", "-o", str(tmp_path / "run"),
                           *options.split()], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("given, expected", [(None, "passive"), ("active", "active")])
def test_jobs_threads_sleep_while_they_wait_unless_told_otherwise(tmp_path, monkeypatch,
                                                                  given, expected):
    # Spinning threads cost 5 times the wall time where another job shares the cores.
    fake = tmp_path / "capsim"
    fake.write_text("#!/bin/sh\necho \"policy=$OMP_WAIT_POLICY\"\n")
    fake.chmod(0o755)
    if given is None:
        monkeypatch.delenv("OMP_WAIT_POLICY", raising=False)
    else:
        monkeypatch.setenv("OMP_WAIT_POLICY", given)
    log = tmp_path / "job.log"
    monkeypatch.chdir(tmp_path)
    assert run_job(str(fake), TINY_SPEC, str(log), threads=1) == 0
    assert f"policy={expected}\n" in log.read_text()


def test_keep_going_finishes_the_other_runs_and_names_the_failed_one(tmp_path):
    write_config(tmp_path, BAD_RUN_CONFIG)
    proc = snakemake(tmp_path, "--keep-going", "results/mesh/table.csv",
                     "results/grid/table.csv")
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0, out[-3000:]
    # The other runs finished, and the study without a failed run has its table, with the
    # run that stopped on contact as a row of its own.
    for seed in (1, 2):
        assert (tmp_path / f"results/mesh/ca0.4_phi0.2_M2_level2_seed{seed}/summary.json").exists()
    assert not (tmp_path / BAD_RUN / "summary.json").exists()
    assert not (tmp_path / "results/mesh/table.csv").exists()
    grid = read_table(tmp_path / "results/grid/table.csv")
    assert sorted(grid["ended"]) == ["contact", "t_end", "t_end"], grid
    assert "stopped early" in out
    # The failed run is named with capsim's message and its log, at the end of the output.
    log = f"results/logs/mesh/{Path(BAD_RUN).name}.log"
    message = "capsim: error: ewald.patch_level: must be at most mesh_level (1)"
    failed = f"run {BAD_RUN} FAILED (exit status 2): {message}"
    tail = proc.stderr[proc.stderr.index("Failed jobs of this snakemake (1)"):]
    assert failed in tail and f"log: {log}" in tail, tail
    assert message in (tmp_path / log).read_text()


def test_killed_run_resumes_and_a_second_snakemake_is_locked_out(tmp_path):
    write_config(tmp_path, LONG_RUN_CONFIG)
    target = f"{LONG_RUN}/summary.json"
    first = subprocess.Popen(snakemake_cmd(tmp_path, target), stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
    try:
        # Wait until capsim has written a few checkpoints: each replaces checkpoint.h5
        # (a new file renamed into place). Only stat: a reader that opens the HDF5 files
        # while capsim appends can make capsim fail to open them (exit 4).
        checkpoints = set()

        def checkpointed():
            try:
                checkpoints.add((tmp_path / LONG_RUN / "checkpoint.h5").stat().st_ino)
            except FileNotFoundError:
                pass
            return len(checkpoints) >= 3
        wait_for(checkpointed, "the run's first checkpoints")
        pids = capsim_pids(tmp_path)
        assert len(pids) == 1, pids
        # Paused, so that it is still running whatever the load: the second snakemake
        # takes seconds to start.
        os.kill(pids[0], signal.SIGSTOP)

        # A second snakemake for the same run, while the first runs it: refused.
        second = snakemake(tmp_path, target)
        assert second.returncode != 0
        assert "LockException" in second.stderr, second.stderr[-2000:]
        assert "Directory cannot be locked" in second.stderr
        assert "--unlock" in second.stderr

        # SIGKILL to capsim (paused or not): the job fails, names the signal, and keeps
        # the checkpoint.
        os.kill(pids[0], signal.SIGKILL)
        out, _ = first.communicate(timeout=120)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert first.returncode != 0
    assert f"run {LONG_RUN} FAILED (killed by signal 9 (SIGKILL))" in out, out[-3000:]
    assert "its checkpoint is kept: the next snakemake resumes it" in out
    assert (tmp_path / LONG_RUN / "checkpoint.h5").exists()
    assert not (tmp_path / LONG_RUN / "summary.json").exists()
    rows_at_kill = len(read_timeseries(tmp_path / LONG_RUN)["time"])

    # The same command again resumes the run from its checkpoint and finishes it.
    again = snakemake(tmp_path, target)
    assert again.returncode == 0, (again.stdout + again.stderr)[-3000:]
    summary = json.loads((tmp_path / LONG_RUN / "summary.json").read_text())
    assert summary["resumed"] is True and summary["ended"] == "t_end"
    assert summary["t_end"] >= 80
    assert len(read_timeseries(tmp_path / LONG_RUN)["time"]) > rows_at_kill
    log = (tmp_path / f"results/logs/grid/{Path(LONG_RUN).name}.log").read_text()
    assert "resuming from its checkpoint" in log and f"--resume {LONG_RUN}" in log


def test_second_job_for_a_running_run_is_refused(tmp_path, capsys, monkeypatch):
    # What a second snakemake started after --unlock would do while the first's capsim
    # still runs: the log is locked, so the job refuses before touching the folder.
    log = tmp_path / "run.log"
    monkeypatch.chdir(tmp_path)
    with open(log, "ab") as held:
        fcntl.flock(held.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        status = run_job(str(CAPSIM), TINY_SPEC, str(log), threads=1)
    assert status == 1
    assert "is already running" in capsys.readouterr().err
    assert not (tmp_path / "results").exists() and log.read_text() == ""

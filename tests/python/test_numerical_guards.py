"""Numerical guards (docs/reliability.md): a checkpoint holding NaN, Inf or an impossible
state is refused on --resume before any step, with one line naming the file and the
dataset, and the run folder stays as it was; summary.json is strict JSON (no NaN or
Infinity) for a finished run and for one that stopped before its averaging window."""

import hashlib
import json
import shutil
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
TINY = ["--set", "mesh_level=1", "--set", "t_end=0.2", "--set", "t_avg_start=0",
        "--set", "output.snapshot_interval=0"]


def capsim(*args):
    return subprocess.run([str(CAPSIM), *map(str, args)], capture_output=True, text=True,
                          timeout=120)


def digest(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def strict_json(text):
    """json.loads that refuses NaN, Infinity and -Infinity, which JSON does not have."""
    def refuse(name):
        raise ValueError(f"summary.json holds {name}")
    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory):
    if not CAPSIM.exists():
        pytest.fail(f"{CAPSIM} is missing: build first (bash scripts/setup.sh)")
    out = tmp_path_factory.mktemp("guards") / "run"
    proc = capsim("run", "-q", *TINY, "-o", out)
    assert proc.returncode == 0, proc.stderr
    return out


# (dataset, index, value): what a corrupt checkpoint may hold.
CORRUPTIONS = [
    ("/positions", (5, 1), np.nan),
    ("/positions", (0, 0), np.inf),
    ("/positions", (11, 2), -np.inf),
    ("/volume0", (0,), np.nan),
    ("/volume0", (0,), -1.0),
    ("/time", (), np.nan),
    ("/time", (), np.inf),
    ("/next_dt", (), np.nan),
]


@pytest.mark.parametrize("dataset, index, value", CORRUPTIONS)
def test_a_non_finite_checkpoint_is_refused_before_any_step(finished_run, tmp_path,
                                                            dataset, index, value):
    run = tmp_path / "run"
    shutil.copytree(finished_run, run)
    with h5py.File(run / "checkpoint.h5", "r+") as f:
        data = f[dataset][()]
        if index:
            data[index] = value
        else:
            data = value
        f[dataset][()] = data
    before = digest(run)
    proc = capsim("run", "-q", "--resume", run, "--set", "t_end=0.4")
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 4, proc.stderr
    assert len(lines) == 1 and lines[0].startswith("capsim: error: checkpoint "), lines
    assert str(run / "checkpoint.h5") in lines[0] and dataset in lines[0], lines[0]
    assert digest(run) == before  # not a byte written: no summary, no rows, no run.yaml


def test_a_broken_but_finite_state_is_refused(finished_run, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(finished_run, run)
    with h5py.File(run / "checkpoint.h5", "r+") as f:
        x = f["/positions"][()]
        x[3] *= 100.0  # one node far out: the membrane has blown up
        f["/positions"][()] = x
    before = digest(run)
    proc = capsim("run", "-q", "--resume", run, "--set", "t_end=0.4")
    assert proc.returncode == 4, proc.stderr
    assert "/positions in capsule 0: the membrane has blown up" in proc.stderr
    assert digest(run) == before


def test_the_summary_of_a_finished_run_is_strict_json(finished_run):
    s = strict_json((finished_run / "summary.json").read_text())
    assert s["ended"] == "t_end"
    assert all(isinstance(s[k], float) for k in ("taylor_D", "mu_sp", "N1", "N2"))


def test_the_summary_of_a_stopped_run_is_strict_json_with_nulls(tmp_path):
    """Two capsules that 'touch' at once (stop_distance 1): the run stops at its first
    step, before t_avg_start, so its averages have no values: null, never NaN."""
    out = tmp_path / "stopped"
    proc = capsim("run", "-q", "--set", "phi=0.3", "--set", "capsules=2", "--set",
                  "mesh_level=1", "--set", "suspension.stop_distance=1", "--set",
                  "t_end=1", "--set", "t_avg_start=0.5", "-o", out)
    assert proc.returncode == 3, proc.stderr
    s = strict_json((out / "summary.json").read_text())
    assert s["ended"] == "contact" and s["sample_values"] == 0
    for key in ("taylor_D", "taylor_D_std", "theta_D_deg", "theta_D_std_deg", "mu_sp",
                "N1", "N2", "energy_mean"):
        assert s[key] is None, key
    assert s["stresslet"] == [[None] * 3] * 3

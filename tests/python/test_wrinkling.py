"""membrane.wrinkling end to end: a short run with the relaxed (tension-field) membrane
runs, records it, writes the compression series and the element tensions, carries no
compressive tension, and resumes to the same bits; the same run with the paper's
membrane shows where that one is compressed."""

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from analysis.read_run import read_timeseries

ROOT = Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
sys.path.insert(0, str(ROOT / "tests" / "reliability"))
import kill_resume_soak  # noqa: E402

TRIANGLES = 80  # mesh level 1
# Ca 0.6: in the first strain units much of a capsule's membrane is compressed. A sample
# every step, a checkpoint every second one; t_end 0.3 and 0.6 fall on the step grid.
CASE = ["mesh_level=1", "ca=0.6", "dt=0.05", "t_end=0.6", "t_avg_start=0.2",
        "output.checkpoint_interval=0.1", "output.snapshot_interval=0.3", "threads=1"]


@pytest.fixture(scope="module")
def runs(capsim_run):
    return (capsim_run("wrinkling", *CASE, "membrane.wrinkling=true"),
            capsim_run("paper", *CASE))


def element_tensions(run, index):
    with h5py.File(run / "snapshots" / f"snapshot_{index:06d}.h5", "r") as f:
        return f["element_tension_max"][()], f["element_tension_min"][()]


def test_the_run_records_the_key(runs):
    wrinkling, paper = runs
    for run, value in ((wrinkling, True), (paper, False)):
        summary = json.loads((run / "summary.json").read_text())
        assert summary["ended"] == "t_end"
        assert summary["parameters"]["membrane.wrinkling"] is value
        assert f"wrinkling: {str(value).lower()}" in (run / "run.yaml").read_text()


def test_the_compression_series_are_written(runs):
    for run in runs:
        ts = read_timeseries(run)
        n = ts["time"].size
        assert ts["compressed_elements"].shape == (n, 1)
        assert ts["min_tension"].shape == (n, 1)
        count = ts["compressed_elements"]
        assert np.array_equal(count, np.round(count))
        assert count.min() >= 0 and count.max() <= TRIANGLES
        # The sphere at t = 0 is stress-free; then the shear compresses part of it, and
        # the count agrees with the most compressive tension.
        assert count[0, 0] == 0 and abs(ts["min_tension"][0, 0]) < 1e-12
        assert count[-1, 0] > 0
        assert np.all((count > 0) == (ts["min_tension"] < -1e-3))


def test_the_relaxed_membrane_carries_no_compression(runs):
    wrinkling, paper = runs
    t1, t2 = element_tensions(wrinkling, 2)
    assert t2.shape == t1.shape == (TRIANGLES,)
    assert np.all(t2 >= 0) and np.all(t1 >= t2)
    assert np.any(t2 == 0) and np.any(t2 > 0)  # wrinkled and taut elements
    _, paper_t2 = element_tensions(paper, 2)
    assert paper_t2.min() < -1e-3  # the paper's membrane is compressed there
    with h5py.File(wrinkling / "snapshots" / "snapshot_000002.h5", "r") as f:
        assert np.all(f["tension_min"][()] >= 0)  # the node means too


def test_a_resumed_wrinkling_run_equals_the_whole_one(runs, tmp_path):
    wrinkling, _ = runs
    part = tmp_path / "part"
    sets = [arg for s in CASE + ["membrane.wrinkling=true"] for arg in ("--set", s)]
    subprocess.run([str(CAPSIM), "run", "-q", *sets, "--set", "t_end=0.3", "-o", str(part)],
                   check=True)
    subprocess.run([str(CAPSIM), "run", "-q", "--resume", str(part), "--set", "t_end=0.6"],
                   check=True)
    assert kill_resume_soak.differences(wrinkling, part) == []

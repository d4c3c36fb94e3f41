"""analysis.read_run on a synthetic run directory whose averages are known by hand.

The synthetic run has M = 2 capsules sampled at t = 0, 2, 4, 6, 8, 10, with linear ramps
    D[t, 0] = 0.1 t,   D[t, 1] = 0.1 t + 0.2,
so over 4 <= t <= 8 the six values are 0.4 0.6 0.8 | 0.6 0.8 1.0: mean 0.7, squared
deviations 0.09 0.01 0.01 0.01 0.01 0.09 (sum 0.22), population std sqrt(0.22 / 6).
"""

import json
import math

import h5py
import numpy as np
import pytest

from analysis import read_summary, read_timeseries, time_average

TIMES = np.array([0.0, 2.0, 4.0, 6.0, 8.0, 10.0])
M = 2


def make_series():
    n = TIMES.size
    d = np.stack([0.1 * TIMES, 0.1 * TIMES + 0.2], axis=1)
    stresslet = np.zeros((n, M, 3, 3))
    stresslet[:, :, 0, 1] = stresslet[:, :, 1, 0] = TIMES[:, None]  # S_xy = t
    stresslet[:, 1, 0, 0] = 1.0  # S_xx = 0 for capsule 0, 1 for capsule 1
    centroid = np.zeros((n, M, 3))
    centroid[:, 1, 0] = 3.0
    return {
        "time": TIMES,
        "step": np.arange(n, dtype=np.int64) * 100,
        "D": d,
        "theta_D_deg": np.full((n, M), 30.0),
        "principal_diff": 2.0 * d,
        "theta_S_deg": np.full((n, M), 35.0),
        "energy": d**2,
        "volume_error": np.full((n, M), 1e-7),
        "volume_drift": np.full((n, M), 2e-7),
        "stresslet": stresslet,
        "centroid": centroid,
    }


def write_run(run_dir, series, skip=(), extra=None):
    run_dir.mkdir(parents=True, exist_ok=True)
    with h5py.File(run_dir / "timeseries.h5", "w") as f:
        for key, value in series.items():
            if key in skip:
                continue
            name = key if key in ("time", "step") else "capsule/" + key
            f.create_dataset(name, data=value)
        for name, value in (extra or {}).items():
            f.create_dataset(name, data=value)
    return run_dir


@pytest.fixture
def run_dir(tmp_path):
    return write_run(tmp_path / "run", make_series())


def test_read_summary_returns_the_json(tmp_path):
    summary = {"parameters": {"ca": 0.2, "phi": 0.0}, "D": {"mean": 0.7, "count": 6}}
    (tmp_path / "summary.json").write_text(json.dumps(summary), encoding="utf-8")
    assert read_summary(tmp_path) == summary
    assert read_summary(str(tmp_path))["parameters"]["ca"] == 0.2


def test_read_summary_missing_file_names_it(tmp_path):
    with pytest.raises(FileNotFoundError, match="summary.json"):
        read_summary(tmp_path)


def test_read_timeseries_round_trip(run_dir):
    want = make_series()
    got = read_timeseries(run_dir)
    assert set(got) == set(want)
    for key, value in want.items():
        np.testing.assert_array_equal(got[key], value, err_msg=key)
    assert got["step"].dtype == np.int64
    assert got["stresslet"].shape == (6, 2, 3, 3)
    assert got["centroid"].shape == (6, 2, 3)


def test_read_timeseries_keeps_extra_datasets(tmp_path):
    extra = {"global/particle_stress": np.ones((TIMES.size, 3, 3))}
    got = read_timeseries(write_run(tmp_path / "run", make_series(), extra=extra))
    assert got["global/particle_stress"].shape == (6, 3, 3)


def test_read_timeseries_reads_the_later_series_where_present(tmp_path):
    """A file of this version has compressed_elements and min_tension (and
    repelled_nodes); one of an older version lacks them and still reads."""
    later = {"repelled_nodes": np.zeros((TIMES.size, M)),
             "compressed_elements": np.tile([3.0, 0.0], (TIMES.size, 1)),
             "min_tension": np.tile([-0.4, 0.2], (TIMES.size, 1))}
    got = read_timeseries(write_run(tmp_path / "new", {**make_series(), **later}))
    for key, value in later.items():
        np.testing.assert_array_equal(got[key], value, err_msg=key)
    assert not any(key.startswith("capsule/") for key in got)
    old = read_timeseries(write_run(tmp_path / "old", make_series()))
    assert not set(later) & set(old)
    short = {**make_series(), "min_tension": np.zeros((TIMES.size - 1, M))}
    with pytest.raises(ValueError, match="/capsule/min_tension has shape"):
        read_timeseries(write_run(tmp_path / "short", short))


def test_read_timeseries_missing_dataset(tmp_path):
    run = write_run(tmp_path / "run", make_series(), skip=("energy",))
    with pytest.raises(ValueError, match="/capsule/energy is missing"):
        read_timeseries(run)


def test_read_timeseries_wrong_shape(tmp_path):
    series = make_series()
    series["centroid"] = series["centroid"][:-1]  # one row short
    with pytest.raises(ValueError, match="/capsule/centroid has shape"):
        read_timeseries(write_run(tmp_path / "run", series))


def test_time_average_linear_ramp_by_hand(run_dir):
    ts = read_timeseries(run_dir)
    mean, std, count = time_average(ts["D"], ts["time"], 4.0, 8.0)
    assert count == 6  # 3 samples (t = 4, 6, 8; both ends included) x 2 capsules
    assert mean == pytest.approx(0.7, rel=1e-12)
    assert std == pytest.approx(math.sqrt(0.22 / 6), rel=1e-12)
    _, std1, _ = time_average(ts["D"], ts["time"], 4.0, 8.0, ddof=1)
    assert std1 == pytest.approx(math.sqrt(0.22 / 5), rel=1e-12)


def test_time_average_single_sample_window():
    d = make_series()["D"]
    mean, std, count = time_average(d, TIMES, 3.0, 5.0)  # only t = 4
    assert (mean, std, count) == (pytest.approx(0.5), pytest.approx(0.1), 2)


def test_time_average_one_dimensional_series():
    # The ramp 0, 2, ..., 10 itself: mean 5, deviations -5 -3 -1 1 3 5.
    mean, std, count = time_average(TIMES, TIMES, 0.0, 10.0)
    assert count == 6
    assert mean == pytest.approx(5.0)
    assert std == pytest.approx(math.sqrt(70 / 6))


def test_time_average_keeps_tensor_components():
    stresslet = make_series()["stresslet"]
    mean, std, count = time_average(stresslet, TIMES, 4.0, 8.0)
    assert count == 6
    assert mean.shape == (3, 3)
    want = np.zeros((3, 3))
    want[0, 1] = want[1, 0] = 6.0  # mean of t over 4, 6, 8
    want[0, 0] = 0.5  # capsule 0 has 0, capsule 1 has 1
    np.testing.assert_allclose(mean, want, rtol=0, atol=1e-14)
    assert std[0, 0] == pytest.approx(0.5)
    assert std[0, 1] == pytest.approx(math.sqrt(8 / 3))  # deviations -2 0 2, twice


def test_time_average_empty_window_raises():
    with pytest.raises(ValueError, match="no samples"):
        time_average(make_series()["D"], TIMES, 10.5, 20.0)


def test_time_average_shape_mismatch_raises():
    with pytest.raises(ValueError, match="does not match"):
        time_average(np.zeros((5, 2)), TIMES, 0.0, 10.0)


def _summary(run_dir, ended, t_avg_start=4.0):
    summary = {"parameters": {"ca": 0.2, "phi": 0.1, "capsules": M, "seed": 1,
                              "mesh_level": 2},
               "t_avg_start": t_avg_start, "ended": ended}
    if ended != "t_end":
        summary["end_message"] = "capsules 0 and 1 touch"
    (run_dir / "summary.json").write_text(json.dumps(summary), encoding="utf-8")
    return run_dir


def test_tables_keep_stopped_runs_with_what_they_have(tmp_path, capsys):
    from analysis import tables
    whole = _summary(write_run(tmp_path / "whole", make_series()), "t_end")
    early = {k: v[:4] for k, v in make_series().items()}  # stopped after t = 6
    stopped = _summary(write_run(tmp_path / "stopped", early), "contact")
    too_early = {k: v[:2] for k, v in make_series().items()}  # stopped after t = 2
    lost = _summary(write_run(tmp_path / "lost", too_early), "contact")
    out = tmp_path / "table.csv"
    tables.main(["--out", str(out), str(whole), str(stopped), str(lost)])
    rows = tables.read_table(out)
    assert list(rows["ended"]) == ["t_end", "contact", "contact"]
    assert list(rows["t_end"]) == [10.0, 6.0, 2.0]
    assert rows["D"][1] == pytest.approx((0.4 + 0.6 + 0.6 + 0.8) / 4)
    # The run stopped before its window: its parameters and no averages.
    assert rows["count"][2] == 0 and math.isnan(rows["D"][2]) and rows["phi"][2] == 0.1
    assert tables.with_data(rows).equals(rows[:2])
    assert "no averages" in capsys.readouterr().err


def test_tables_refuse_a_finished_run_without_samples_in_its_window(tmp_path):
    from analysis import tables
    short = {k: v[:2] for k, v in make_series().items()}
    run = _summary(write_run(tmp_path / "short", short), "t_end")
    with pytest.raises(ValueError, match="no samples"):
        tables.main(["--out", str(tmp_path / "t.csv"), str(run)])

"""The dilute-table helpers on synthetic summaries with known answers."""

import json
import math
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

from analysis.fits import observed_order

ROOT = Path(__file__).resolve().parents[2]


def test_observed_order_of_a_second_order_sequence():
    # f(h) = 1 + 3 h^2 with h = 0.4, 0.2, 0.1
    f = [1 + 3 * h * h for h in (0.4, 0.2, 0.1)]
    assert math.isclose(observed_order(*f), 2.0, rel_tol=1e-12)


def write_series(run_dir, d, s_xy):
    """A one-capsule timeseries.h5 at t = 0, 1, ..., 19 with the given D and S_xy series
    (the other series constant)."""
    n = len(d)
    stresslet = np.zeros((n, 1, 3, 3))
    stresslet[:, 0, 0, 1] = stresslet[:, 0, 1, 0] = s_xy
    series = {"D": np.reshape(d, (n, 1)), "theta_D_deg": np.full((n, 1), 40.0),
              "principal_diff": np.ones((n, 1)), "theta_S_deg": np.full((n, 1), 45.0),
              "energy": np.zeros((n, 1)), "volume_error": np.zeros((n, 1)),
              "volume_drift": np.zeros((n, 1)), "stresslet": stresslet,
              "centroid": np.zeros((n, 1, 3))}
    with h5py.File(run_dir / "timeseries.h5", "w") as f:
        f.create_dataset("time", data=np.arange(n, dtype=float))
        f.create_dataset("step", data=np.arange(n, dtype=np.int64))
        for key, value in series.items():
            f.create_dataset("capsule/" + key, data=value)


def test_table_end_to_end(tmp_path):
    paths = []
    for level, h in ((2, 0.4), (3, 0.2), (4, 0.1)):
        d = tmp_path / f"run{level}"
        d.mkdir()
        s = {"taylor_D": 0.1 + h * h, "theta_D_deg": 40 + h, "mu_sp": 2.5 - h * h,
             "N1": 1.0, "N2": -0.2, "t_avg_start": 10.0,
             "parameters": {"ca": 0.05, "mesh_level": level}}
        (d / "summary.json").write_text(json.dumps(s))
        # D alternates by +-0.001 about its value, S_xy is constant (standard error 0).
        write_series(d, 0.1 + h * h + 0.001 * (-1.0) ** np.arange(20), np.ones(20))
        paths.append(str(d / "summary.json"))
    md, csv_path = tmp_path / "t.md", tmp_path / "t.csv"
    subprocess.run([sys.executable, str(ROOT / "figures/dilute_table.py"), "--out-md", str(md),
                    "--out-csv", str(csv_path)] + paths, check=True, capture_output=True)
    text = md.read_text()
    # The window [10, 19] holds 10 samples, anticorrelated: tau_int is its floor 1/2 and
    # the standard error s / sqrt(10).
    se = f"{np.std(0.001 * (-1.0) ** np.arange(10, 20), ddof=1) / math.sqrt(10):.2g}"
    assert f"| 0.05 | D | 0.26 +- {se} | 0.14 +- {se} | 0.11 +- {se} | 2.00 |" in text
    assert "| 0.05 | [mu] | 2.34 +- 0 |" in text
    assert "| 0.05 | theta_D (deg) |" in text and "1.00 |" in text
    assert "(25/12) Ca = 0.10417" in text

"""A real (tiny) capsim run read back through analysis/: the Python averages agree with
summary.json, and every dataset that snapshots.xdmf names exists with its stated shape."""

import json
import math
import subprocess
import xml.etree.ElementTree as ET

import h5py
import pytest

from analysis.read_run import read_summary, read_timeseries, time_average
from analysis.rheology import stress_factor
from conftest import CAPSIM


@pytest.fixture(scope="module")
def run_dir(capsim_run):
    return capsim_run("run", "mesh_level=1", "ca=0.3", "t_end=1", "t_avg_start=0.5",
                      "output.snapshot_interval=0.5")


def test_python_averages_match_the_summary(run_dir):
    s = read_summary(run_dir)
    ts = read_timeseries(run_dir)
    mean_d, std_d, count = time_average(ts["D"], ts["time"], s["t_avg_start"], s["t_end"])
    assert count == s["sample_values"]
    assert math.isclose(mean_d, s["taylor_D"], rel_tol=1e-12)
    assert math.isclose(std_d, s["taylor_D_std"], rel_tol=1e-9, abs_tol=1e-15)
    mean_s, _, _ = time_average(ts["stresslet"], ts["time"], s["t_avg_start"], s["t_end"])
    mu = stress_factor(0.0, 0.3) * mean_s[0, 1]  # intrinsic [mu] (phi = 0)
    assert math.isclose(mu, s["mu_sp"], rel_tol=1e-12)


def test_xdmf_names_existing_datasets(run_dir):
    root = ET.parse(run_dir / "snapshots.xdmf").getroot()
    grids = root.findall(".//Grid[@GridType='Uniform']")
    assert len(grids) == 3  # t = 0, 0.5, 1
    for item in root.iter("DataItem"):
        file_name, dataset = item.text.strip().split(":")
        dims = tuple(int(d) for d in item.get("Dimensions").split())
        with h5py.File(run_dir / file_name, "r") as f:
            assert f[dataset].shape == dims


def test_the_profile_accounts_for_the_steps(tmp_path):
    """capsim run --profile: the stages nest (the evaluations within the stepping within
    the loop; the Ewald stages and the membrane load within the evaluations), two
    evaluations per Heun step (no snapshots, whose velocity field is one more), and
    every stage that ran has a positive time."""
    out, profile = tmp_path / "run", tmp_path / "profile.json"
    subprocess.run([str(CAPSIM), "run", "-q", "--set", "ca=0.3", "--set", "phi=0.2",
                    "--set", "capsules=2", "--set", "mesh_level=1", "--set", "t_end=0.5",
                    "--set", "t_avg_start=0.1", "--set", "threads=1",
                    "--set", "output.snapshot_interval=0", "-o", str(out),
                    "--profile", str(profile)], check=True)
    p = json.loads(profile.read_text())
    s = p["seconds"]
    assert p["steps"] == json.loads((out / "summary.json").read_text())["steps"]
    assert p["evaluations"] == 2 * p["steps"] and p["real_space_pairs_per_evaluation"] > 0
    parts = ["membrane_load", "ewald_setup", "near_corrections", "real_space", "reciprocal",
             "volume_rate"]
    assert all(s[k] > 0 for k in parts + ["spreading", "fft", "gathering", "sampling"])
    assert sum(s[k] for k in parts) <= s["evaluations"] <= s["stepping"] <= s["loop"]
    assert s["spreading"] + s["fft"] + s["gathering"] <= s["reciprocal"]
    assert s["unbounded_single_layer"] == 0
    assert s["double_layer_setup"] == s["double_layer_apply"] == 0  # lambda 1: no solve


def test_the_profile_times_the_double_layer_of_another_viscosity_ratio(tmp_path):
    """At lambda 5 each evaluation solves the second-kind equation: the profile's
    double_layer_setup (once per solve) and double_layer_apply (once per GMRES
    iteration and for the first residual) ran, within the evaluations, beside the
    single layer's Ewald stages."""
    out, profile = tmp_path / "run", tmp_path / "profile.json"
    subprocess.run([str(CAPSIM), "run", "-q", "--set", "ca=0.3", "--set", "phi=0.2",
                    "--set", "capsules=2", "--set", "mesh_level=1", "--set", "t_end=0.3",
                    "--set", "t_avg_start=0.1", "--set", "threads=1", "--set", "lambda=5",
                    "--set", "output.snapshot_interval=0", "-o", str(out),
                    "--profile", str(profile)], check=True)
    s = json.loads(profile.read_text())["seconds"]
    layers = ["double_layer_setup", "double_layer_apply", "ewald_setup",
              "near_corrections", "real_space", "reciprocal"]
    assert all(s[k] > 0 for k in layers)
    assert sum(s[k] for k in layers) <= s["evaluations"]


def test_single_precision_grids_move_a_short_run_by_their_rounding(tmp_path):
    """ewald.precision auto at tolerance 1e-3 takes the single-precision grids (1e-7 of
    the reciprocal sum, tests/cpp/test_spectral_ewald.cpp): over a few steps the samples
    move by about that, far below the tolerance, and they do move (the single path ran)."""
    def run(precision):
        out = tmp_path / precision
        subprocess.run([str(CAPSIM), "run", "-q", "--set", "ca=0.3", "--set", "phi=0.2",
                        "--set", "capsules=2", "--set", "mesh_level=1", "--set",
                        "t_end=0.3", "--set", "t_avg_start=0.1", "--set", "threads=1",
                        "--set", "ewald.tolerance=1e-3", "--set",
                        f"ewald.precision={precision}", "-o", str(out)], check=True)
        return read_timeseries(out)["stresslet"]
    double, single = run("double"), run("auto")
    difference = abs(single - double).max() / abs(double).max()
    assert 0 < difference < 1e-5

"""Every figure script on synthetic inputs with known answers: the scripts run, write
PNG/PDF/CSV, and the CSV holds the values the synthetic data were built from."""

import json
import math
import runpy
import sys
from pathlib import Path

import h5py
import matplotlib.pyplot as plt
import numpy as np
import pytest

from analysis import coefficients
from analysis.rheology import stress_factor
from analysis.statistics import standard_error
from analysis.tables import COLUMNS, read_table, select, write_table

ROOT = Path(__file__).resolve().parents[2]
CAS = [0.1, 0.3]
PHIS = [0.05, 0.1, 0.2, 0.3]
SE = 0.01  # every standard error of the synthetic rows


def a_coef(ca):
    return 2.5 - 2.0 * ca, 5.0 - 5.0 * ca  # a1, a2 of the synthetic mu_sp


def b_coef(ca):
    return 1.0 + 3.0 * ca, 4.0 + ca  # b1, b2 of the synthetic N1


def synthetic_row(ca, phi):
    """A run row whose mu_sp and N1 are exact quadratics in phi (b2, a2 known)."""
    a1, a2 = a_coef(ca)
    b1, b2 = b_coef(ca)
    intrinsic = phi == 0
    scale = 1.0 if intrinsic else phi
    mu = a1 * scale + (0 if intrinsic else a2 * phi**2)
    n1 = b1 * scale + (0 if intrinsic else b2 * phi**2)
    factor = stress_factor(phi, ca)
    s12, s11_22 = mu / factor, n1 / factor
    diff = math.hypot(2 * s12, s11_22)
    theta = 0.5 * math.degrees(math.atan2(2 * s12, s11_22))
    return {"ca": ca, "phi": phi, "capsules": 4, "seed": 1, "mesh_level": 2, "t_start": 10,
            "t_end": 100, "count": 100, "D": 2 * ca + 0.3 * phi, "D_std": 0.01 + phi,
            "theta_D_deg": 30 - 10 * phi, "theta_D_std_deg": 1 + phi, "principal_diff": diff,
            "theta_S_deg": theta, "S_xx": s11_22, "S_xy": s12, "S_yy": 0.0, "S_zz": 0.0,
            "mu_sp": mu, "N1": n1, "N2": -0.1 * n1, "S12": s12, "S12_principal": s12,
            "S11_S22": s11_22, "S11_S22_principal": s11_22,
            "sin2theta_S": math.sin(math.radians(2 * theta)),
            "cos2theta_S": math.cos(math.radians(2 * theta)), "intrinsic": int(intrinsic),
            "run": f"synthetic/ca{ca}_phi{phi}",
            **{c: SE for c in COLUMNS if c.endswith(("_se", "_se_deg"))}}


@pytest.fixture(scope="module")
def grid_table(tmp_path_factory):
    path = tmp_path_factory.mktemp("grid") / "table.csv"
    rows = [synthetic_row(ca, phi) for ca in CAS for phi in [0.0] + PHIS]
    write_table(path, rows, COLUMNS)
    return path


COEFFICIENT_FIGURES = ("fig05", "fig06", "fig07", "fig08", "fig10")  # read results/grid/fits.csv


def run_script(script, *args):
    """Runs a figure script under figures/ as its command line does, in this process:
    the same __main__ block, without a new interpreter importing matplotlib and pandas
    again (about 3 s a call)."""
    argv, path = sys.argv, list(sys.path)
    sys.argv = [str(script), *map(str, args)]
    sys.path.insert(0, str(script.parent))  # a script imports its folder's common
    try:
        runpy.run_path(str(script), run_name="__main__")
    except SystemExit as stop:
        assert not stop.code, f"{script} exited with {stop.code}"
    finally:
        sys.argv, sys.path[:] = argv, path
        plt.close("all")


def run_figure(name, out_dir, *inputs):
    """Run one figure script as the workflow does; a figure drawn with the section 4.2
    coefficients is given the grid table and its coefficient table (analysis.coefficients)."""
    out = out_dir / name
    if name in COEFFICIENT_FIGURES and len(inputs) == 1:
        fits_table = out_dir / f"{name}_fits.csv"
        assert coefficients.main(["--out", str(fits_table), str(inputs[0])]) == 0
        inputs = (*inputs, fits_table)
    run_script(ROOT / "figures" / f"{name}.py", "--out", out, *inputs)
    for ext in ("png", "pdf", "csv"):
        assert (out_dir / f"{name}.{ext}").stat().st_size > 0
    return read_table(out_dir / f"{name}.csv")


@pytest.mark.parametrize("name", ["fig03", "fig04", "fig06", "fig08", "fig09", "fig10"])
def test_grid_figures_run(name, grid_table, tmp_path):
    assert not run_figure(name, tmp_path, grid_table).empty


def test_a_run_stopped_before_its_window_changes_no_coefficient(tmp_path):
    # A row as analysis.tables writes it for a run that stopped before t_start: count 0,
    # NaN averages. The figures leave it out of every plot and fit (and name it below).
    rows = [synthetic_row(ca, phi) for ca in CAS for phi in [0.0] + PHIS]
    stopped = {key: float("nan") for key in COLUMNS}
    stopped.update({"ca": CAS[0], "phi": 0.4, "capsules": 4, "seed": 1, "mesh_level": 2,
                    "t_start": 10, "t_end": 3.5, "count": 0, "intrinsic": 0,
                    "ended": "numerical", "run": "synthetic/stopped"})
    path = tmp_path / "table.csv"
    write_table(path, rows + [stopped], COLUMNS)
    out = run_figure("fig05", tmp_path, path)
    for ca in CAS:
        (row,) = select(out, panel="b", ca=ca).to_dict("records")
        assert (row["a1"], row["a2"]) == pytest.approx(a_coef(ca))
    for name in ("fig03", "fig07", "fig10"):
        assert not run_figure(name, tmp_path, path).empty


def test_fig05_recovers_a1_a2_and_krieger_dougherty(grid_table, tmp_path):
    rows = run_figure("fig05", tmp_path, grid_table)
    for ca in CAS:
        (row,) = select(rows, panel="b", ca=ca).to_dict("records")
        assert (row["a1"], row["a2"]) == pytest.approx(a_coef(ca))
    (kd,) = select(rows, series="krieger-dougherty").to_dict("records")
    assert kd["a2"] == pytest.approx(5.109, abs=1e-3)


def test_fig07_recovers_b1_b2(grid_table, tmp_path):
    rows = run_figure("fig07", tmp_path, grid_table)
    for ca in CAS:
        (row,) = select(rows, panel="d", ca=ca).to_dict("records")
        assert (row["b1"], row["b2"]) == pytest.approx(b_coef(ca))


def test_fig06_shares_of_an_exact_quadratic(grid_table, tmp_path):
    rows = run_figure("fig06", tmp_path, grid_table)
    (row,) = select(rows, ca=0.1, phi=0.3).to_dict("records")
    assert row["higher_share"] == pytest.approx(0.0, abs=1e-12)
    a1, a2 = a_coef(0.1)
    assert row["first_share"] == pytest.approx(a1 * 0.3 / (a1 * 0.3 + a2 * 0.09))


def test_fig10_ratio_is_one_plus_a2_over_a1_phi(grid_table, tmp_path):
    rows = run_figure("fig10", tmp_path, grid_table)
    (row,) = select(rows, panel="a", ca=0.3, phi=0.2).to_dict("records")
    a1, a2 = a_coef(0.3)
    assert row["ratio"] == pytest.approx(1 + a2 / a1 * 0.2)


@pytest.mark.parametrize("name, slope", [("fig03", 0.3), ("fig04", -10.0)])
def test_fig03_fig04_slope_and_its_standard_error(name, slope, grid_table, tmp_path):
    # <D> and <theta_D> are exact lines in phi with equal errors SE: the weighted fit has
    # chi^2 = 0 and the slope's error SE / sqrt(sum (phi - mean phi)^2).
    rows = run_figure(name, tmp_path, grid_table)
    phi = np.array([0.0] + PHIS)
    (row,) = select(rows, ca=0.1, phi=0.2).to_dict("records")
    assert row["slope"] == pytest.approx(slope)
    assert row["slope_se"] == pytest.approx(SE / np.sqrt(np.sum((phi - phi.mean()) ** 2)))


def test_figure_data_carry_the_standard_errors(grid_table, tmp_path):
    rows = run_figure("fig03", tmp_path, grid_table)
    assert (rows[["D_se", "D_std_se"]] == SE).all().all()
    rows = run_figure("fig04", tmp_path, grid_table)
    assert (rows[["theta_D_se_deg", "theta_D_std_se_deg"]] == SE).all().all()
    rows = run_figure("fig09", tmp_path, grid_table)
    assert (rows[["S12_se", "S12_principal_se", "theta_S_se_deg"]] == SE).all().all()
    rows = run_figure("fig06", tmp_path, grid_table)
    assert (rows.dropna(subset=["higher_share_se"])["higher_share_se"] > 0).all()


def test_fig05_a2_standard_error_propagates_the_fit(grid_table, tmp_path):
    # a2 = sum(p^2 (y - a1 p)) / sum(p^4) over p = 0.05, 0.1: linear in y and a1.
    rows = run_figure("fig05", tmp_path, grid_table)
    p = np.array([0.05, 0.1])
    s4 = np.sum(p**4)
    want = SE * math.sqrt(np.sum(p**4) + np.sum(p**3) ** 2) / s4
    (row,) = select(rows, panel="b", ca=0.1).to_dict("records")
    assert row["a1_se"] == SE and row["a2_se"] == pytest.approx(want)


def test_coefficients_without_a_phi_in_the_fitting_range(tmp_path):
    # A Ca whose suspension runs all lie above phi_max has a1 but no a2, b2: NaN in the
    # table, and the figures still draw it (figure 6 without the share errors).
    rows = [synthetic_row(ca, phi) for ca in CAS for phi in [0.0] + PHIS]
    rows = [r for r in rows if not (r["ca"] == CAS[1] and 0 < r["phi"] <= 0.1)]
    path = tmp_path / "table.csv"
    write_table(path, rows, COLUMNS)
    out = run_figure("fig05", tmp_path, path)
    (row,) = select(out, panel="b", ca=CAS[1]).to_dict("records")
    assert row["a1"] == pytest.approx(a_coef(CAS[1])[0]) and math.isnan(row["a2"])
    shares = run_figure("fig06", tmp_path, path)
    assert select(shares, ca=CAS[1])["first_share_se"].isna().all()
    assert select(shares, ca=CAS[0])["first_share_se"].notna().all()


def test_fig10_ratio_standard_error(grid_table, tmp_path):
    rows = run_figure("fig10", tmp_path, grid_table)
    (row,) = select(rows, panel="a", ca=0.3, phi=0.2).to_dict("records")
    y, sol = synthetic_row(0.3, 0.2)["S12"], synthetic_row(0.3, 0.0)["S12"]
    want = y / sol * math.hypot(SE / y, SE / sol)
    assert row["ratio_se"] == pytest.approx(want, rel=1e-3)
    assert select(rows, panel="a", ca=0.3, phi=0.0)["ratio_se"].iloc[0] == 0.0


def test_fig12_mean_of_cases_standard_error_and_spread(tmp_path):
    rows = []
    for m in (2, 4):
        for seed, (d, se) in enumerate([(0.30, 0.03), (0.32, 0.04), (0.34, 0.12)], 1):
            row = synthetic_row(0.2, 0.3) | {"capsules": m, "seed": seed, "D": d, "D_se": se}
            rows.append(row)
    path = tmp_path / "boxsize.csv"
    write_table(path, rows, COLUMNS)
    out = run_figure("fig12", tmp_path, path)
    (row,) = select(out, quantity="D", capsules=4).to_dict("records")
    assert row["mean"] == pytest.approx(0.32)
    assert row["std"] == pytest.approx(0.02 * math.sqrt(2 / 3))
    assert row["se"] == pytest.approx(0.13 / 3)


def test_table1_prints_value_and_standard_error(tmp_path):
    rows = [synthetic_row(0.2, 0.3) | {"mesh_level": 1, "D": 0.36, "D_se": 0.0026}]
    rows += [synthetic_row(0.2, 0.3) | {"mesh_level": 2, "seed": s, "D": d, "D_se": se}
             for s, (d, se) in enumerate([(0.37, 0.03), (0.38, 0.04), (0.39, 0.12)], 1)]
    path = tmp_path / "mesh.csv"
    write_table(path, rows, COLUMNS)
    run_script(ROOT / "figures" / "table1.py", "--out", tmp_path / "table1", path)
    text = (tmp_path / "table1.md").read_text()
    assert "| 80 | 0.36000 +- 0.0026 |" in text
    assert "| 320 (average): reference | 0.38000 +- 0.043 | - |" in text
    assert "standard deviation of the cases" in text.lower()
    table = read_table(tmp_path / "table1.csv")
    ref = select(table, seed="mean").iloc[0]
    assert ref["D_se"] == pytest.approx(0.13 / 3)
    assert ref["D_std"] == pytest.approx(0.01 * math.sqrt(2 / 3))
    # eps_D = |x / r - 1|, r = 0.38 the mean of the cases: the coarse run is independent of
    # r, so se^2 = (se_x / r)^2 + (x se_r / r^2)^2; case 1 (0.37) is one of the three
    # averaged in r, so d/dx_1 = 1/r - x_1 / (3 r^2) and d/dx_j = -x_1 / (3 r^2). The
    # central differences of the propagation differ from the derivatives by
    # O((se_r / r)^2), 1 % here; leaving out the correlation would be 13 % off.
    r, r_se = 0.38, 0.13 / 3
    coarse = select(table, N_E=80).iloc[0]
    assert coarse["eps_D"] == pytest.approx(0.02 / r)
    assert coarse["eps_D_se"] == pytest.approx(math.hypot(0.0026 / r, 0.36 * r_se / r**2),
                                               rel=0.02)
    case = select(table, N_E=320, seed=1).iloc[0]
    terms = [(1 / r - 0.37 / (3 * r**2)) * 0.03]
    terms += [0.37 / (3 * r**2) * e for e in (0.04, 0.12)]
    assert case["eps_D_se"] == pytest.approx(math.sqrt(np.sum(np.square(terms))), rel=0.02)
    # mu_sp is the same in every run (eps_mu = 0), each with the error SE.
    assert coarse["eps_mu"] == pytest.approx(0, abs=1e-12)
    assert coarse["eps_mu_se"] == pytest.approx(
        math.hypot(SE, SE / math.sqrt(3)) / coarse["mu_sp"], rel=1e-4)
    assert f"| 80 | 0.36000 +- 0.0026 | 0.0526 +- {coarse['eps_D_se']:.2g} |" in text


def write_initial_run(run_dir, seed, d):
    """A run of 2 capsules at t = 0, 0.5, ..., with D = d (n, 2), S_xy = 1, for figure 11."""
    run_dir.mkdir(parents=True)
    n, m = d.shape
    stresslet = np.zeros((n, m, 3, 3))
    stresslet[..., 0, 1] = stresslet[..., 1, 0] = 1.0
    with h5py.File(run_dir / "timeseries.h5", "w") as f:
        f.create_dataset("time", data=0.5 * np.arange(n))
        f.create_dataset("step", data=np.arange(n, dtype=np.int64))
        for key, value in {"D": d, "theta_D_deg": np.full((n, m), 30.0),
                           "principal_diff": np.ones((n, m)), "theta_S_deg": np.ones((n, m)),
                           "energy": np.zeros((n, m)), "volume_error": np.zeros((n, m)),
                           "volume_drift": np.zeros((n, m)), "stresslet": stresslet,
                           "centroid": np.zeros((n, m, 3))}.items():
            f.create_dataset("capsule/" + key, data=value)
    summary = {"parameters": {"ca": 0.2, "phi": 0.3, "capsules": m, "seed": seed,
                              "mesh_level": 1}, "t_avg_start": 10.0}
    (run_dir / "summary.json").write_text(json.dumps(summary))
    return run_dir / "summary.json"


def test_fig11_running_standard_error_and_the_cases(tmp_path):
    rng = np.random.default_rng(11)
    runs, last_se = [], []
    for seed in (1, 2, 3):
        d = 0.3 + 0.01 * rng.standard_normal((61, 2))
        runs.append(write_initial_run(tmp_path / f"seed{seed}", seed, d))
        last_se.append(standard_error(d, 0.5 * np.arange(61), 10.0, 30.0))
    rows = run_figure("fig11", tmp_path, *runs)
    per_seed = rows[rows["seed"].astype(str) != "mean"]
    # Every t_e from 10.5 (two samples in the window) carries the running standard error.
    assert per_seed["D_se"].notna().all() and (per_seed["mu_sp_se"] == 0.0).all()
    last = per_seed[per_seed["t_e"] == 30.0].sort_values("seed")
    assert list(last["D_se"]) == pytest.approx(last_se)
    (final,) = select(rows, seed="mean").dropna(subset=["D"]).to_dict("records")
    assert final["D_se"] == pytest.approx(math.sqrt(np.sum(np.square(last_se))) / 3)
    assert final["D_std"] > 0 and final["cases"] == 3

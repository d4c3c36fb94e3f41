"""Every figure script on synthetic inputs with known answers: the scripts run, write
PNG/PDF/CSV, and the CSV holds the values the synthetic data were built from."""

import math
import subprocess
import sys
from pathlib import Path

import pytest

from analysis.rheology import stress_factor
from analysis.tables import COLUMNS, read_table, select, write_table

ROOT = Path(__file__).resolve().parents[2]
CAS = [0.1, 0.3]
PHIS = [0.05, 0.1, 0.2, 0.3]


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
            "run": f"synthetic/ca{ca}_phi{phi}"}


@pytest.fixture(scope="module")
def grid_table(tmp_path_factory):
    path = tmp_path_factory.mktemp("grid") / "table.csv"
    rows = [synthetic_row(ca, phi) for ca in CAS for phi in [0.0] + PHIS]
    write_table(path, rows, COLUMNS)
    return path


def run_figure(name, out_dir, *inputs):
    out = out_dir / name
    subprocess.run([sys.executable, str(ROOT / "figures" / f"{name}.py"), "--out", str(out),
                    *map(str, inputs)], check=True, capture_output=True, text=True)
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


def test_fig03_slope(grid_table, tmp_path):
    rows = run_figure("fig03", tmp_path, grid_table)
    assert select(rows, ca=0.1, phi=0.2)["slope"].iloc[0] == pytest.approx(0.3)

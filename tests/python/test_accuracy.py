"""The accuracy study: its error split on series with a known answer, and the study's
small variant (config/ci.yaml) end to end through the workflow."""

import math

import pandas as pd
import pytest

from analysis.accuracy import (convergent_order, discretisation_errors, pareto_front,
                               plan, time_options)
from test_workflow_ci import ROOT, snakemake, pytestmark  # noqa: F401 (skips without capsim)


def test_observed_order_and_richardson_error_of_a_power_law():
    # v(level) = 1 + 0.3 h^2 with h halving per level: order 2, and the finest level's
    # error from the two finest levels is exact for a pure power law.
    values = {level: 1.0 + 0.3 * 4.0**-level for level in (1, 2, 3)}
    assert convergent_order(values) == pytest.approx(2.0, rel=1e-12)
    errors, p = discretisation_errors(values)
    assert p == pytest.approx(2.0, rel=1e-12)
    assert errors[3] == pytest.approx(0.3 * 4.0**-3 / values[3], rel=1e-12)
    assert errors[1] == pytest.approx((values[1] - values[3]) / values[3], rel=1e-12)


def test_order_not_observed_falls_back_to_the_nominal_order():
    values = {1: 1.0, 2: 1.01, 3: 1.0}  # the differences do not shrink
    errors, p = discretisation_errors(values)
    assert math.isnan(p)
    assert errors[3] == pytest.approx(errors[2] / 3.0)  # nominal order 2: 2^2 - 1


def test_pareto_front():
    nan = float("nan")
    front = pareto_front([1, 2, 3, 2, 3, 4, nan], [3, 2, 1, 3, 3, nan, 0.5])
    assert front.tolist() == [True, True, True, False, False, False, False]


def test_bad_time_setting_is_named():
    with pytest.raises(ValueError, match="'rk4' is not heun<dt_safety>"):
        time_options("rk4")


def test_time_codes_name_the_error_norm():
    assert "time.error_norm=rms" in time_options("imexrms0.01")
    assert not any("error_norm" in o for o in time_options("imex1e-3"))  # max, default
    assert "time.tolerance=0.01" in time_options("imexrms0.01")


def test_ci_accuracy_study(tmp_path):
    proc = snakemake(tmp_path, "accuracy")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    table = pd.read_csv(tmp_path / "results" / "accuracy" / "errors.csv")
    suspension = table[table["case"] == "suspension"]
    # base, a second level, an Ewald tolerance, a time setting, an M, a window and the
    # configuration's own run: each a point with every part measured.
    assert len(suspension) == 8
    for q in ("D", "mu_sp", "N1"):
        parts = suspension[[f"{q}_{p}" for p in ("disc", "ewald", "time", "stat")]]
        assert parts.notna().all().all() and (suspension[f"{q}_total"] > 0).all()
        assert suspension[f"{q}_pareto"].any()
    assert (table["cpu_s_per_strain"] > 0).all()
    for ext in ("png", "pdf", "csv"):
        assert (tmp_path / "results" / "figures" / f"speed_error.{ext}").stat().st_size > 0


def test_plan_of_the_default_configuration_has_a_dozen_settings():
    import yaml
    block = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["accuracy"]
    suspension = {(p.run, p.window) for p in plan(block) if p.case == "suspension"}
    assert len(suspension) >= 12

"""The limit eb -> 0 of the bending membranes (analysis/bending_limit.py): which points and
runs it plans, the extrapolation and its errors, on values whose answer is known."""

import math

import numpy as np
import pytest

from analysis import bending_limit as bl

GRID = {"mesh_level": 3, "capsules": 27, "seeds": [1],
        "membranes": [{"ca": 0.5, "phi": 0.1, "membrane": "eb0.025"},
                      {"ca": 0.6, "phi": 0.4, "membrane": "rep5+eb0.025"},
                      {"ca": 0.3, "phi": 0.3, "membrane": "wrinkling"}]}


def test_the_points_are_the_grid_points_with_bending_and_keep_their_other_tokens():
    points = bl.points(GRID)
    assert [(p.ca, p.phi, p.code) for p in points] == [(0.5, 0.1, "eb0.025"),
                                                       (0.6, 0.4, "eb0.025+rep5")]
    assert points[1].eb == 0.025 and points[1].at(0.0125) == "eb0.0125+rep5"


def test_the_dilute_cases_cover_every_ca_at_every_modulus():
    assert bl.dilute_cases({"eb": [0.0125]}, GRID) == [
        (0.5, 0.0125), (0.5, 0.025), (0.6, 0.0125), (0.6, 0.025)]


@pytest.mark.parametrize("eb", [[0], [-0.01], [1.5]])
def test_a_modulus_outside_the_range_is_named(eb):
    with pytest.raises(ValueError, match="eblimit.eb"):
        bl.moduli({"eb": eb})


def test_two_moduli_give_the_line_through_both_and_its_propagated_error():
    value, se = bl.limit([0.0125, 0.025], [0.497, 0.476], [0.003, 0.004])
    assert value == pytest.approx(0.518)
    # y0 = 2 y1 - y2: se = sqrt((2 se1)^2 + se2^2)
    assert se == pytest.approx(math.hypot(2 * 0.003, 0.004))


def test_three_moduli_give_the_weighted_least_squares_intercept():
    eb = np.array([0.0125, 0.025, 0.05])
    values = 0.52 - 1.7 * eb + np.array([1e-3, -2e-3, 1e-3])
    errors = np.array([1e-3, 2e-3, 1e-3])
    value, se = bl.limit(eb, values, errors)
    design = np.vstack([np.ones_like(eb), eb]).T / errors[:, None]
    fit, *_ = np.linalg.lstsq(design, values / errors, rcond=None)
    covariance = np.linalg.inv(design.T @ design)
    assert value == pytest.approx(fit[0], rel=1e-12)
    assert se == pytest.approx(math.sqrt(covariance[0, 0]), rel=1e-9)


def _row(eb, scale, se=1e-3):
    """A run's averages that fall linearly with eb (slope -scale per unit eb, relative)."""
    out = {"eb": eb, "t_start": 10.0, "t_end": 30.0, "ended": "t_end"}
    for q in bl.QUANTITIES:
        out[q] = 1.0 - scale * eb
        out[bl.SE.get(q, f"{q}_se")] = se
    return out


def test_a_point_extrapolates_and_carries_the_dilute_miss_as_its_model_error():
    point = bl.points(GRID)[0]
    runs = [_row(0.0125, 2.0), _row(0.025, 2.0)]
    # One capsule: linear in eb as well, but its eb = 0 run lies 1 % above the line.
    dilute = [_row(0.0125, 1.0, 1e-5), _row(0.025, 1.0, 1e-5)]
    reference = {q: 1.0 / 0.99 for q in bl.QUANTITIES}
    row = bl.point_row(point, runs, dilute, reference)
    for q in bl.QUANTITIES:
        assert row[q] == pytest.approx(1.0)
        assert row[f"{q}_eb"] == pytest.approx(0.95)
        assert row[f"{q}_correction"] == pytest.approx(1 / 0.95 - 1)
        assert row[f"{q}_model"] == pytest.approx(0.01)
        statistical = math.hypot(2e-3, 1e-3)
        assert row[bl.SE.get(q, f"{q}_se")] == pytest.approx(math.hypot(statistical, 0.01))
    assert row["moduli"] == "0.0125 0.025" and row["ended"] == "t_end t_end"


def test_every_average_of_a_run_row_is_extrapolated_and_the_stresslet_without_error():
    row = {"ca": 0.5, "phi": 0.1, "t_end": 30.0, "count": 200, "D": 0.5, "D_se": 1e-3,
           "theta_D_deg": 20.0, "theta_D_se_deg": 0.1, "S_xy": 1.0, "membrane": "eb0.025",
           "ended": "t_end", "volume_error_max": 1e-4, "intrinsic": 0}
    assert bl.averaged_columns(row) == [("D", "D_se"), ("theta_D_deg", "theta_D_se_deg"),
                                        ("S_xy", None)]


def test_a_dilute_value_near_zero_gives_no_relative_miss():
    dilute = [{"eb": 0.0125, "D_std": 1e-4, "D_std_se": 1e-4},
              {"eb": 0.025, "D_std": 2e-4, "D_std_se": 1e-4}]
    assert bl.relative_miss(dilute, {"D_std": 5e-4, "D_std_se": 1e-4}, "D_std",
                            "D_std_se") is None
    assert bl.relative_miss(dilute, {"D_std": 0.1, "D_std_se": 1e-4}, "D_std",
                            "D_std_se") == pytest.approx(-1.0)


def test_the_paper_membrane_table_replaces_only_the_points_with_bending():
    import pandas as pd

    grid = pd.DataFrame([
        {"ca": 0.5, "phi": 0.05, "intrinsic": 0, "D": 0.48, "D_se": 1e-3, "t_end": 30.0,
         "ended": "t_end", "membrane": "paper"},
        {"ca": 0.5, "phi": 0.1, "intrinsic": 0, "D": 0.45, "D_se": 1e-3, "t_end": 30.0,
         "ended": "t_end", "membrane": "eb0.025"},
        {"ca": 0.5, "phi": 0.0, "intrinsic": 1, "D": 0.47, "D_se": 1e-4, "t_end": 30.0,
         "ended": "t_end", "membrane": "paper"}])
    limits = pd.DataFrame([{"ca": 0.5, "phi": 0.1, "D": 0.49, "D_se": 4e-3, "D_eb": 0.45,
                            "moduli": "0.0125 0.025", "ended": "contact t_end",
                            "window_end": 24.0, "membrane": "eb0.025"}])
    out = bl.paper_membrane(grid, limits)
    assert list(out["D"]) == [0.48, 0.49, 0.47] and list(out["D_se"]) == [1e-3, 4e-3, 1e-4]
    assert list(out["membrane"]) == ["paper"] * 3
    assert list(out["obtained"]) == ["run", "eb -> 0 from eb 0.0125 0.025", "run"]
    assert out.loc[1, "t_end"] == 24.0 and out.loc[1, "ended"] == "contact"
    assert "D_eb" not in out


def test_a_point_whose_run_stopped_early_in_its_window_has_no_limit_and_says_why():
    point = bl.points(GRID)[0]
    stopped = {**_row(0.0125, 2.0), "t_end": 11.07, "ended": "contact"}
    row = bl.point_row(point, [stopped, _row(0.025, 2.0)], [_row(0.0125, 1.0, 1e-5),
                       _row(0.025, 1.0, 1e-5)], {q: 1.0 for q in bl.QUANTITIES},
                       min_window=10.0)
    assert math.isnan(row["D"]) and row["D_eb"] == pytest.approx(0.95)
    assert row["short"] == "eb 0.0125 stopped at 11.1 (contact), window under 10"


def test_a_run_stopped_early_is_left_out_and_the_line_goes_through_the_others():
    point = bl.points(GRID)[0]
    stopped = {**_row(0.0125, 5.0), "D": 0.2, "t_end": 16.2, "ended": "numerical"}
    runs = [stopped, _row(0.025, 2.0), _row(0.05, 2.0)]
    # One capsule: exact on the line through 0.025 and 0.05, off it at 0.0125.
    dilute = [{**_row(0.0125, 1.0, 1e-5), "D": 0.5}, _row(0.025, 1.0, 1e-5),
              _row(0.05, 1.0, 1e-5)]
    row = bl.point_row(point, runs, dilute, {q: 1.0 for q in bl.QUANTITIES},
                       min_window=10.0)
    assert row["moduli"] == "0.025 0.05" and row["ended"] == "t_end t_end"
    assert row["D"] == pytest.approx(1.0) and row["D_model"] == pytest.approx(0.0)
    assert row["short"] == "eb 0.0125 stopped at 16.2 (numerical), window under 10"


def test_more_gives_single_points_a_further_modulus_and_its_dilute_runs():
    block = {"eb": [0.0125], "more": [{"ca": 0.6, "phi": 0.4, "eb": 0.05}]}
    first, second = bl.points(GRID)
    assert bl.point_moduli(block, first, GRID) == [0.0125]
    assert bl.point_moduli(block, second, GRID) == [0.0125, 0.05]
    assert (0.6, 0.05) in bl.dilute_cases(block, GRID)
    assert (0.5, 0.05) not in bl.dilute_cases(block, GRID)
    with pytest.raises(ValueError, match="eblimit.more: Ca 0.3 phi 0.3"):
        bl.point_moduli({"eb": [0.0125], "more": [{"ca": 0.3, "phi": 0.3, "eb": 0.05}]},
                        first, GRID)

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
    out = {"eb": eb, "t_end": 30.0, "ended": "t_end"}
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
        assert row[f"{q}_se"] == pytest.approx(math.hypot(statistical, 0.01))
    assert row["moduli"] == "0.0125 0.025" and row["ended"] == "t_end t_end"

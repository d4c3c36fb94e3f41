"""The split of an O(phi^3) share's standard error by input (analysis.share_budget)
against its first-order formula."""

import numpy as np
import pandas as pd
import pytest

from analysis.share_budget import budget, lengthened, pair_runs, plan, share_se


def test_each_input_alone_and_all_together_follow_the_delta_method():
    y, c1, c2, phi = 1.5, 2.0, 3.0, 0.4
    se_y, se_c1, se_c2 = 1e-3, 2e-3, 5e-2
    table = pd.DataFrame([{"ca": 0.1, "phi": 0.4, "mu_sp": y, "mu_sp_se": se_y,
                           "t_end": 30.0},
                          {"ca": 0.1, "phi": 0.1, "mu_sp": 0.3, "mu_sp_se": 1.0,
                           "t_end": 30.0}])
    fits = pd.DataFrame([{"ca": 0.1, "a1": c1, "a1_se": se_c1, "a2": c2, "a2_se": se_c2}])
    row = budget(table, fits, phi).iloc[0]
    low = c1 * phi + c2 * phi**2
    assert row.share == pytest.approx(1 - low / y, rel=1e-14)
    # d/dy = low / y^2; the central difference of 1/y is off by (se_y / y)^2 relative.
    assert row.se_from_mu_sp == pytest.approx(low / y**2 * se_y, rel=1e-5)
    assert row.se_from_a1 == pytest.approx(phi * se_c1 / y, rel=1e-12)  # linear: exact
    assert row.se_from_a2 == pytest.approx(phi**2 * se_c2 / y, rel=1e-12)
    assert row.se == pytest.approx(np.sqrt(row.se_from_mu_sp**2 + row.se_from_a1**2
                                           + row.se_from_a2**2), rel=1e-12)


def _grid(se_low=1e-3, se_high=0.04):
    """One Ca's dilute row (no error) and its runs at phi 0.05, 0.1 and 0.4, [10, 30]."""
    def row(phi, y, se):
        return {"ca": 0.3, "phi": phi, "intrinsic": int(phi == 0), "count": 100,
                "mu_sp": y, "mu_sp_se": se, "N1": y, "N1_se": se, "t_start": 10.0,
                "t_end": 30.0, "ended": "t_end"}
    return pd.DataFrame([row(0.0, 1.9, 0.0), row(0.05, 0.097, se_low),
                         row(0.1, 0.20, se_low), row(0.4, 1.04, se_high)])


def test_the_plan_lengthens_to_the_target_by_the_square_root_of_the_window():
    # se_high small: the central difference of 1/y errs by (se / y)^2 relative.
    table = _grid(se_high=0.004)
    now = share_se(table, 0.3, 0.4)
    row = plan(table, 0.4, 0.5 * now, {}).iloc[0]
    assert row.se == pytest.approx(now, rel=1e-12)
    assert row.floor == pytest.approx(share_se(_grid(0.0, 0.0), 0.3, 0.4), abs=1e-12)
    # Every error falls as the window's square root: half the error, four times the
    # window (to the root finder's 0.1 strain units).
    assert row.t_end_needed - 10.0 == pytest.approx(4 * 20.0, abs=0.1)
    longer = lengthened(table, 0.3, 0.4, row.t_end_needed, {})
    assert share_se(longer, 0.3, 0.4) == pytest.approx(0.5 * now, rel=1e-3)
    kept = ["mu_sp_se", "t_end"]  # the dilute run is not lengthened
    assert (longer.loc[0, kept] == table.loc[0, kept]).all()


def test_an_extrapolations_model_part_is_a_floor_no_run_length_passes():
    table = _grid()
    model = {(0.3, 0.4): 0.03}  # of the 0.04 at phi 0.4, 0.03 does not fall with the window
    row = plan(table, 0.4, 1e-3, model).iloc[0]
    floor_y = (1.9 * 0.4 + ((0.097 - 1.9 * 0.05) * 0.05**2 + (0.20 - 0.19) * 0.1**2)
               / (0.05**4 + 0.1**4) * 0.4**2) / 1.04**2 * 0.03  # d share / d y times 0.03
    assert row.floor == pytest.approx(floor_y, rel=1e-3)
    assert np.isinf(row.t_end_needed)
    target = (row.floor + row.se) / 2
    reached = plan(table, 0.4, target, model).iloc[0]
    longer = lengthened(table, 0.3, 0.4, reached.t_end_needed, model)
    assert share_se(longer, 0.3, 0.4) == pytest.approx(target, rel=1e-3)
    assert longer.loc[3, "mu_sp_se"] > 0.03


def test_a_target_already_met_needs_no_longer_run():
    table = _grid(se_low=1e-5, se_high=1e-4)
    row = plan(table, 0.4, 0.01, {}).iloc[0]
    assert row.t_end_needed == 30.0 and row.stopped == ""


def test_the_runs_of_an_extrapolated_pair_are_lengthened_each_on_its_own_window():
    # The limit 2 f(0.0125) - f(0.025): the grid's run (eb 0.025) to 55 with error 0.02,
    # the other to 100 with 0.01, a model part 0.005 (eblimit.t_end_at).
    stat = np.hypot(2 * 0.01, 0.02)
    limits = pd.DataFrame([{"ca": 0.3, "phi": 0.4, "membrane": "eb0.025+rep5",
                            "moduli": "0.0125 0.025", "t_end": "100 55", "mu_sp": 1.0,
                            "mu_sp_se": np.hypot(stat, 0.005), "mu_sp_eb_se": 0.02,
                            "mu_sp_model": 0.005}])
    runs = pair_runs(limits)
    assert runs[(0.3, 0.4)] == [pytest.approx((2.0, 0.01, 100.0)),
                                pytest.approx((-1.0, 0.02, 55.0))]
    table = _grid()
    table.loc[3, ["mu_sp_se", "t_end"]] = limits.mu_sp_se[0], 55.0
    model = {(0.3, 0.4): 0.005}
    for t_end, var in [(190.0, 4e-4 * 90 / 180 + 4e-4 * 45 / 180),  # both lengthened
                       (80.0, 4e-4 + 4e-4 * 45 / 70)]:  # the longer run kept as it is
        longer = lengthened(table, 0.3, 0.4, t_end, model, runs=runs)
        assert longer.loc[3, "mu_sp_se"] == pytest.approx(np.hypot(np.sqrt(var), 0.005),
                                                          rel=1e-12)
    # As one run from the shorter window, the error at 190 would be too small.
    alone = lengthened(table, 0.3, 0.4, 190.0, model).loc[3, "mu_sp_se"]
    assert alone < np.hypot(np.sqrt(4e-4 * 90 / 180 + 4e-4 * 45 / 180), 0.005)

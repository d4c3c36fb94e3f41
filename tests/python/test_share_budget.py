"""The split of an O(phi^3) share's standard error by input (analysis.share_budget)
against its first-order formula."""

import numpy as np
import pandas as pd
import pytest

from analysis.share_budget import budget


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

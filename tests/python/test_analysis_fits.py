"""analysis.fits, analysis.coefficients and analysis.rheology on synthetic data with known
answers."""

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from analysis import coefficients, fits
from analysis.rheology import box_side, rheology, stress_factor


def test_second_coefficient_recovers_an_exact_quadratic():
    phi = np.array([0.0, 0.02, 0.05, 0.08, 0.1, 0.2, 0.3])
    mu = 2.2 * phi + 4.7 * phi**2
    assert fits.second_coefficient(phi, mu, 2.2) == pytest.approx(4.7, rel=1e-12)


def test_second_coefficient_uses_only_the_fitting_range():
    # A cubic term biases c2 by c3 sum(phi^5)/sum(phi^4) over the points used (phi <= 0.1);
    # the points at 0.2 and 0.3 (with a wild value) must not enter.
    phi = np.array([0.05, 0.1, 0.2, 0.3])
    mu = 2.0 * phi + 4.0 * phi**2 + 10.0 * phi**3
    mu[3] = 100.0
    p = phi[:2]
    want = 4.0 + 10.0 * np.sum(p**5) / np.sum(p**4)  # = 4 + 10 * 0.0943.. = 4.9444..
    assert fits.second_coefficient(phi, mu, 2.0) == pytest.approx(want, rel=1e-12)
    assert want == pytest.approx(4.0 + 10.0 * (0.05**5 + 0.1**5) / (0.05**4 + 0.1**4))


def test_second_coefficient_needs_a_point_in_range():
    with pytest.raises(ValueError, match="no volume fraction"):
        fits.second_coefficient([0.2, 0.3], [1.0, 2.0], 2.0)


def test_order_shares():
    phi = np.array([0.2, 0.4])
    mu = 2.0 * phi + 4.0 * phi**2 + 5.0 * phi**3
    first, second, higher = fits.order_shares(phi, mu, 2.0, 4.0)
    # phi = 0.2: mu = 0.4 + 0.16 + 0.04 = 0.6 -> shares 2/3, 0.56/0.6, 0.04/0.6
    assert first[0] == pytest.approx(0.4 / 0.6)
    assert second[0] == pytest.approx(0.56 / 0.6)
    assert higher[0] == pytest.approx(0.04 / 0.6)
    assert higher[1] == pytest.approx(5.0 * 0.4**3 / mu[1])


def test_kd_coefficients_paper_values():
    # Section 4.2: with phi_m = 0.63, a1 = 2.5 and a2 ~ 5.1 (exactly 2.5 (2.5 + 1/0.63)/2).
    a = fits.kd_coefficients(3, 0.63)
    assert a[0] == pytest.approx(2.5)
    assert a[1] == pytest.approx(2.5 * (2.5 + 1 / 0.63) / 2)
    assert round(a[1], 1) == 5.1
    assert a[2] == pytest.approx(a[1] * (2.5 + 2 / 0.63) / 3)


def test_kd_coefficients_are_the_taylor_series_of_eq_4_7():
    phi = np.linspace(-0.01, 0.01, 41)
    coef = np.polyfit(phi, fits.kd_specific_viscosity(phi, 0.63), 6)[::-1]
    assert coef[0] == pytest.approx(0.0, abs=1e-10)
    assert coef[1:4] == pytest.approx(fits.kd_coefficients(3, 0.63), rel=1e-6)


def test_kd_rigid_sphere_shares_match_the_paper_text():
    # Section 4.2: for rigid spheres (KD, phi_m = 0.63) O(phi^3) terms are ~15 % of mu_sp
    # at phi = 0.2 and ~50 % at phi = 0.4.
    a1, a2 = fits.kd_coefficients(2, 0.63)
    phi = np.array([0.2, 0.4])
    _, _, higher = fits.order_shares(phi, fits.kd_specific_viscosity(phi), a1, a2)
    assert higher[0] == pytest.approx(0.15, abs=0.02)
    assert higher[1] == pytest.approx(0.50, abs=0.05)  # 0.533: "approximately 50 %"


def test_fit_kd_max_packing_recovers_phi_m():
    phi = np.array([0.05, 0.1, 0.2, 0.3, 0.4])
    mu = fits.kd_specific_viscosity(phi, 0.55, intrinsic=2.1)
    assert fits.fit_kd_max_packing(phi, mu, intrinsic=2.1) == pytest.approx(0.55, rel=1e-6)


def weighted_slope_error(x, se):
    """The slope's standard error of a straight line fitted with weights w = 1/se^2, in
    closed form: sqrt(S / (S Sxx - Sx^2)), S = sum w, Sx = sum w x, Sxx = sum w x^2."""
    w = 1.0 / np.asarray(se) ** 2
    s, sx, sxx = w.sum(), (w * x).sum(), (w * x**2).sum()
    return math.sqrt(s / (s * sxx - sx**2))


def test_linear_fit():
    c0, c1, c1_se = fits.linear_fit([0, 0.1, 0.2, 0.3], [0.3, 0.33, 0.36, 0.39])
    assert (c0, c1) == pytest.approx((0.3, 0.3)) and math.isnan(c1_se)


def test_weighted_linear_fit_of_an_exact_line():
    # Exact data: the line itself, and the slope's error from the points' errors alone.
    x = np.array([0.0, 0.05, 0.1, 0.2, 0.3])
    se = np.array([0.001, 0.01, 0.02, 0.01, 0.04])
    c0, c1, c1_se = fits.linear_fit(x, 0.2 + 0.5 * x, se)
    assert (c0, c1) == pytest.approx((0.2, 0.5))
    assert c1_se == pytest.approx(weighted_slope_error(x, se), rel=1e-9)


def test_weighted_linear_fit_scales_by_the_reduced_chi_square_above_one():
    # Residuals +-r orthogonal to 1 and x leave the line where it was, with
    # chi^2 = 4 r^2 / se^2 over N - 2 = 2: reduced 2 for r = se, 0.02 for r = se / 10.
    x, se = np.array([0.0, 1.0, 2.0, 3.0]), np.full(4, 0.5)
    pattern = np.array([1.0, -1.0, -1.0, 1.0])
    bare = weighted_slope_error(x, se)
    _, c1, c1_se = fits.linear_fit(x, 1.0 + 2.0 * x + 0.5 * pattern, se)
    assert c1 == pytest.approx(2.0) and c1_se == pytest.approx(math.sqrt(2.0) * bare)
    _, _, c1_se = fits.linear_fit(x, 1.0 + 2.0 * x + 0.05 * pattern, se)
    assert c1_se == pytest.approx(bare)


def test_weighted_linear_fit_matches_the_spread_of_slopes():
    # Gaussian noise of the stated errors, 4000 draws: the fitted slopes scatter by the
    # closed-form error, and the reported error is that times sqrt(max(1, chi^2 / 3)),
    # chi^2 with 3 degrees of freedom, on average (13 % above); an unweighted fit scatters
    # twice as much.
    rng = np.random.default_rng(7)
    x = np.array([0.0, 0.05, 0.1, 0.2, 0.3])
    se = np.array([0.002, 0.01, 0.01, 0.03, 0.05])
    ys = 0.2 + 0.5 * x + se * rng.standard_normal((4000, x.size))
    fitted = np.array([fits.linear_fit(x, y, se)[1:] for y in ys])
    spread = fitted[:, 0].std()
    assert spread == pytest.approx(weighted_slope_error(x, se), rel=0.05)
    scale = stats.chi2(3).expect(lambda c: np.sqrt(np.maximum(1.0, c / 3.0)))
    assert fitted[:, 1].mean() == pytest.approx(scale * weighted_slope_error(x, se), rel=0.02)
    assert np.polyfit(x, ys.T, 1)[0].std() > 1.5 * spread


def test_rigid_sphere_stresslet_gives_einstein():
    # A rigid sphere: S_xy = (10/3) pi mu gammadot a^3 = (10/3) pi Ca in Gs a^2 units.
    ca = 0.2
    s = np.zeros((3, 3))
    s[0, 1] = s[1, 0] = 10.0 / 3.0 * math.pi * ca
    r = rheology(s, 0.0, ca)
    assert r["mu_sp"] == pytest.approx(2.5)
    assert r["N1"] == 0 and r["N2"] == 0
    assert rheology(s, 0.1, ca)["mu_sp"] == pytest.approx(0.25)


def test_normal_stress_differences_signs():
    s = np.diag([3.0, 1.0, 0.5])
    r = rheology(s, 0.3, 0.1)
    factor = stress_factor(0.3, 0.1)
    assert r["N1"] == pytest.approx(2.0 * factor)
    assert r["N2"] == pytest.approx(0.5 * factor)


def test_box_side():
    assert box_side(100, 0.3) ** 3 * 0.3 == pytest.approx(100 * 4 * math.pi / 3)


def test_box_side_analytic_values():
    # One sphere of radius 1 in a cube of side 2 fills (4/3) pi / 8 of it; 8 such cubes
    # (M = 8) at the same phi make a cube of side 4.
    assert box_side(1, math.pi / 6) == pytest.approx(2.0, rel=1e-15)
    assert box_side(8, math.pi / 6) == pytest.approx(4.0, rel=1e-15)


def test_stress_factor_analytic_values():
    # 3 phi / (4 pi Ca): phi = 4 pi / 30 at Ca = 0.1 gives 1; phi = 0 gives the intrinsic
    # factor 3 / (4 pi Ca).
    assert stress_factor(4 * math.pi / 30, 0.1) == pytest.approx(1.0, rel=1e-15)
    assert stress_factor(0.0, 0.75 / math.pi) == pytest.approx(1.0, rel=1e-15)
    assert stress_factor(0.2, 0.75 / math.pi) == pytest.approx(0.2, rel=1e-15)


def test_coefficient_table_from_a_grid_table():
    # Two Ca, each with its dilute row (intrinsic values a1, b1) and exact quadratics over
    # phi; a run stopped before its window (count 0) and a Ca without a dilute run are left
    # out.
    rows = []
    for ca, (a1, a2, b1, b2) in {0.1: (2.3, 4.0, 1.2, 3.0), 0.6: (1.6, 1.0, 2.5, 2.0)}.items():
        rows.append({"ca": ca, "phi": 0.0, "intrinsic": 1, "count": 10, "mu_sp": a1,
                     "mu_sp_se": 0.01, "N1": b1, "N1_se": 0.02})
        for phi in (0.05, 0.1, 0.2):
            rows.append({"ca": ca, "phi": phi, "intrinsic": 0, "count": 10,
                         "mu_sp": a1 * phi + a2 * phi**2, "mu_sp_se": 0.01,
                         "N1": b1 * phi + b2 * phi**2, "N1_se": 0.02})
    rows.append({"ca": 0.1, "phi": 0.1, "intrinsic": 0, "count": 0, "mu_sp": math.nan,
                 "mu_sp_se": math.nan, "N1": math.nan, "N1_se": math.nan})
    rows.append({"ca": 0.3, "phi": 0.1, "intrinsic": 0, "count": 10, "mu_sp": 1.0,
                 "mu_sp_se": 0.01, "N1": 1.0, "N1_se": 0.01})
    table = coefficients.coefficient_table(pd.DataFrame(rows), phi_max=0.1)
    assert list(table["ca"]) == [0.1, 0.6]
    (row,) = table[table["ca"] == 0.6].to_dict("records")
    assert (row["a1"], row["a2"], row["b1"], row["b2"]) == pytest.approx((1.6, 1.0, 2.5, 2.0))
    assert row["a1_se"] == 0.01 and row["phi_max"] == 0.1
    # a2 = sum(p^2 (y - a1 p)) / sum(p^4) over p = 0.05, 0.1: linear in the values and a1.
    p = np.array([0.05, 0.1])
    want = math.sqrt(0.01**2 * np.sum(p**4) + (0.01 * np.sum(p**3)) ** 2) / np.sum(p**4)
    assert row["a2_se"] == pytest.approx(want)

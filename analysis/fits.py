"""Polynomial coefficients of mu_sp(phi) and N1(phi), their order shares, and the
Krieger-Dougherty relation (paper section 4.2, eqs. 4.6-4.8 and 4.11).

The procedure of section 4.2: the first coefficient (a1, b1) is the dilute-limit value
([mu], [N1] of one capsule in unbounded shear); the second (a2, b2) is the least-squares
fit of (y - c1 phi) = c2 phi^2 over 0 <= phi <= 0.10. Also the observed order of mesh
convergence of the dilute table, and the weighted straight lines of figures 3a and 4a.
"""

import math

import numpy as np

FIT_PHI_MAX = 0.10  # section 4.2: a2 converged for the fitting range 0 <= phi <= 0.10
PHI_RANDOM_CLOSE = 0.63  # maximum packing of eq. 4.7 (random close packing)
EINSTEIN = 2.5


def second_coefficient(phi, values, first, phi_max=FIT_PHI_MAX):
    """c2 minimising sum (y - c1 phi - c2 phi^2)^2 over 0 < phi <= phi_max.

    The model has no free constant or linear term, so the normal equation gives
    c2 = sum(phi^2 (y - c1 phi)) / sum(phi^4). Points at phi = 0 carry no weight.
    Raises ValueError if no phi lies in (0, phi_max].
    """
    phi = np.asarray(phi, dtype=float)
    values = np.asarray(values, dtype=float)
    use = (phi > 0) & (phi <= phi_max + 1e-12) & np.isfinite(values)
    if not np.any(use):
        raise ValueError(f"no volume fraction in (0, {phi_max}] to fit the second "
                         f"coefficient (phi: {sorted(set(phi.tolist()))})")
    p, y = phi[use], values[use]
    return float(np.sum(p**2 * (y - first * p)) / np.sum(p**4))


def order_shares(phi, values, first, second):
    """Shares of the first-order and first-plus-second-order terms (figures 6 and 8).

    Returns (c1 phi / y, (c1 phi + c2 phi^2) / y, the O(phi^3) share 1 - the second).
    """
    phi = np.asarray(phi, dtype=float)
    values = np.asarray(values, dtype=float)
    first_share = first * phi / values
    second_share = (first * phi + second * phi**2) / values
    return first_share, second_share, 1.0 - second_share


def kd_specific_viscosity(phi, phi_m=PHI_RANDOM_CLOSE, intrinsic=EINSTEIN):
    """Krieger-Dougherty specific viscosity, eq. 4.7: (1 - phi/phi_m)^(-[mu] phi_m) - 1.

    The paper's form has [mu] = 2.5 (rigid spheres); `intrinsic` generalises it.
    """
    phi = np.asarray(phi, dtype=float)
    return (1.0 - phi / phi_m) ** (-intrinsic * phi_m) - 1.0


def kd_coefficients(order, phi_m=PHI_RANDOM_CLOSE, intrinsic=EINSTEIN):
    """Taylor coefficients a_1 .. a_order of eq. 4.7 around phi = 0, eq. 4.8:
    a_i = prod_{n=1..i} (1/n) ([mu] + (n - 1)/phi_m), with [mu] = 5/2 in the paper."""
    coefficients, product = [], 1.0
    for n in range(1, order + 1):
        product *= (intrinsic + (n - 1) / phi_m) / n
        coefficients.append(product)
    return np.array(coefficients)


def fit_kd_max_packing(phi, mu_sp, intrinsic=EINSTEIN, phi_m0=PHI_RANDOM_CLOSE):
    """Least-squares phi_m of eq. 4.7 (with [mu] = `intrinsic`) to data mu_sp(phi).

    Beyond the paper: an effective maximum packing that summarises a capsule curve.
    phi_m is bounded to (max phi, 10]. Returns phi_m.
    """
    phi = np.asarray(phi, dtype=float)
    mu_sp = np.asarray(mu_sp, dtype=float)
    use = (phi > 0) & np.isfinite(mu_sp)
    if np.count_nonzero(use) < 1:
        raise ValueError("no volume fraction > 0 to fit phi_m")
    lower = phi[use].max() * (1 + 1e-9)

    def residual(x):
        return kd_specific_viscosity(phi[use], x[0], intrinsic) - mu_sp[use]

    start = min(max(phi_m0, lower * 1.01), 9.99)
    # Imported here: the workflow imports this module at every start, and scipy.optimize
    # takes about 0.6 s to import.
    from scipy.optimize import least_squares
    return float(least_squares(residual, [start], bounds=([lower], [10.0])).x[0])


def observed_order(coarse, medium, fine):
    """Order p of mesh convergence from three levels with h halving (the dilute table):
    |f_medium - f_coarse| / |f_fine - f_medium| = 2^p. NaN when a difference is 0."""
    d1, d2 = abs(medium - coarse), abs(fine - medium)
    if d1 == 0 or d2 == 0:
        return float("nan")
    return math.log2(d1 / d2)


def linear_fit(x, y, se=None):
    """Intercept, slope and the slope's standard error of the line y = c0 + c1 x
    (figures 3a, 4a): least squares weighted by the points' standard errors `se`
    (weights 1/se^2).

    The slope's error is the fit's, from the points' errors (the unscaled covariance),
    times sqrt(chi^2 / (N - 2)) where that exceeds 1: the points then scatter about the line
    more than their errors allow (the curve is not quite a line, or the errors are low),
    and the scatter is the better measure. It is not scaled down below 1: over a few points
    chi^2 scatters widely, and a small one would understate the error. Without `se`, or
    when an error is not positive and finite, the fit is unweighted and the error NaN.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.size < 2:
        return float(y[0]) if y.size else float("nan"), float("nan"), float("nan")
    se = np.full(x.shape, np.nan) if se is None else np.asarray(se, dtype=float)
    if not np.all(np.isfinite(se) & (se > 0)):
        slope, intercept = np.polyfit(x, y, 1)
        return float(intercept), float(slope), float("nan")
    (slope, intercept), cov = np.polyfit(x, y, 1, w=1.0 / se, cov="unscaled")
    dof = x.size - 2
    chi2 = float(np.sum(((y - intercept - slope * x) / se) ** 2))
    scale = max(1.0, chi2 / dof) if dof > 0 else 1.0
    return float(intercept), float(slope), float(np.sqrt(cov[0, 0] * scale))

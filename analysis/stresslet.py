"""The stresslet decomposition of paper section 4.3 (eqs. 4.12-4.15).

In the shear plane (x-y) the stresslet has principal values S1 >= S2 with S1's axis at
theta_S from the flow direction x. Then (eqs. 4.12, 4.13)
    S_xy = 1/2 (S1 - S2) sin(2 theta_S),   S_xx - S_yy = (S1 - S2) cos(2 theta_S),
and for ensemble averages the approximations (eqs. 4.14, 4.15)
    <S_xy> ~ 1/2 <S1 - S2> sin(2 <theta_S>),  <S_xx - S_yy> ~ <S1 - S2> cos(2 <theta_S>).
"""

import numpy as np


def principal_in_plane(stresslet):
    """S1, S2, theta_S (degrees, in (-90, 90]) of the x-y block of S (shape (..., 3, 3))."""
    s = np.asarray(stresslet, dtype=float)
    sxx, syy, sxy = s[..., 0, 0], s[..., 1, 1], s[..., 0, 1]
    mean = 0.5 * (sxx + syy)
    radius = np.hypot(0.5 * (sxx - syy), sxy)
    theta = 0.5 * np.degrees(np.arctan2(2.0 * sxy, sxx - syy))
    theta = np.where(theta <= -90.0, theta + 180.0, theta)
    return mean + radius, mean - radius, theta


def shear_component(principal_diff, theta_s_deg):
    """S_xy from S1 - S2 and theta_S, eq. 4.12 (eq. 4.14 with ensemble means)."""
    return 0.5 * np.asarray(principal_diff) * np.sin(2.0 * np.radians(theta_s_deg))


def normal_difference(principal_diff, theta_s_deg):
    """S_xx - S_yy from S1 - S2 and theta_S, eq. 4.13 (eq. 4.15 with ensemble means)."""
    return np.asarray(principal_diff) * np.cos(2.0 * np.radians(theta_s_deg))


def decomposition(mean_stresslet, mean_principal_diff, mean_theta_s_deg):
    """Both sides of eqs. 4.14 and 4.15 from a run's averages (figure 9a, b).

    Returns a dict: S12 (<S_xy>), S12_principal (1/2 <S1-S2> sin 2<theta_S>),
    S11_S22 (<S_xx - S_yy>), S11_S22_principal (<S1-S2> cos 2<theta_S>),
    sin2theta_S, cos2theta_S.
    """
    s = np.asarray(mean_stresslet, dtype=float)
    angle = 2.0 * np.radians(mean_theta_s_deg)
    return {
        "S12": float(s[0, 1]),
        "S12_principal": float(shear_component(mean_principal_diff, mean_theta_s_deg)),
        "S11_S22": float(s[0, 0] - s[1, 1]),
        "S11_S22_principal": float(normal_difference(mean_principal_diff,
                                                     mean_theta_s_deg)),
        "sin2theta_S": float(np.sin(angle)),
        "cos2theta_S": float(np.cos(angle)),
    }


def decomposition_gradients(mean_principal_diff, mean_theta_s_deg):
    """The derivatives (d/d<S1-S2>, d/d<theta_S> per degree) of the right-hand sides of
    eqs. 4.14, 4.15 and of sin, cos 2<theta_S>, at the means: a dict name -> (a, b). The
    standard error of such a quantity is that of the time average of the linearised series
    a (S1 - S2)(t) + b theta_S(t) (analysis.averages), which keeps the correlation of the
    two series."""
    p = float(mean_principal_diff)
    angle = 2.0 * np.radians(mean_theta_s_deg)
    per_degree = 2.0 * np.pi / 180.0  # d(2 theta in radians) / d(theta in degrees)
    sin, cos = float(np.sin(angle)), float(np.cos(angle))
    return {"S12_principal": (0.5 * sin, 0.5 * p * cos * per_degree),
            "S11_S22_principal": (cos, -p * sin * per_degree),
            "sin2theta_S": (0.0, cos * per_degree),
            "cos2theta_S": (0.0, -sin * per_degree)}

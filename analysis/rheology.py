"""Particle stress and rheology from the mean stresslet (paper eqs. 4.3-4.5, 4.9, 4.10).

The stresslet is in units of Gs a^2 (docs/conventions.md). With n_c = phi /
(4/3 pi a^3) and Gs = mu gammadot a / Ca, the particle stress over mu gammadot is
Sigma^p = 3 phi / (4 pi Ca) <S> / (Gs a^2).
"""

import math

import numpy as np


def stress_factor(phi, ca):
    """3 phi / (4 pi Ca): the factor of eq. 4.5 from <S> in Gs a^2 to the particle stress
    over mu gammadot. For phi = 0 (the dilute limit) phi is left out, 3 / (4 pi Ca): the
    intrinsic value per unit phi."""
    return 3.0 / (4.0 * math.pi * ca) * (phi if phi > 0 else 1.0)


def particle_stress(mean_stresslet, phi, ca):
    """Sigma^(p) / (mu gammadot) (eq. 4.3) from <S> in Gs a^2.

    For phi = 0 (the dilute limit) phi is left out: the intrinsic stress per unit phi.
    """
    return stress_factor(phi, ca) * np.asarray(mean_stresslet, dtype=float)


def rheology(mean_stresslet, phi, ca):
    """mu_sp (eq. 4.5), N1 (eq. 4.9), N2 (eq. 4.10), all over mu gammadot.

    Axes: x flow, y gradient, z vorticity, so 1-2-3 of the paper's section 4 is x-y-z.
    For phi = 0 these are the intrinsic [mu], [N1], [N2] (per unit phi).
    """
    s = particle_stress(mean_stresslet, phi, ca)
    return {"mu_sp": float(s[0, 1]), "N1": float(s[0, 0] - s[1, 1]),
            "N2": float(s[1, 1] - s[2, 2])}


def box_side(capsules, phi):
    """Side L = cbrt(4 pi M / (3 phi)) of the cubic box holding M capsules of radius 1 at
    volume fraction phi (M (4/3) pi = phi L^3)."""
    return float(np.cbrt(4.0 * math.pi * capsules / (3.0 * phi)))

"""The tank-treading frequency of a capsule in steady shear, from one snapshot's node
velocities (the snapshot files hold them: analysis.snapshots).

In steady tank-treading the shape stands still and the membrane's material points orbit
around it. A point near the shear plane (x, y) goes round once a period T; where its
angle about the centroid is theta, it turns at omega(theta) = (r_x u_y - r_y u_x) /
(r_x^2 + r_y^2), r and u relative to the centroid and its velocity, so

    T = int_0^2pi dtheta / |omega(theta)|,   the frequency 2 pi / T,

the harmonic mean of |omega| over the orbit, in units of the shear rate gammadot (a
rigid sphere turns at gammadot / 2; Keller & Skalak 1982 for an ellipsoid). omega(theta)
is the least-squares Fourier series (up to HARMONICS) through the nodes within BAND of the
shear plane, which smooths the scatter of nodes off the plane and of the mesh.

marker_frequency measures the same from the motion itself, for a run with frequent
snapshots: the time each node near the shear plane takes for its last whole turn about
the centroid. Both agree within 0.2 % at Ca 0.2, level 2
(tests/python/test_tank_treading.py).
"""

import numpy as np

from analysis.snapshots import last_snapshot

BAND = 0.3  # |z - z_c| below this many equivalent radii: the nodes of the orbit
HARMONICS = 4  # of the fit of omega(theta); the ellipse's is the second
GRID = 720  # points of the orbit's integral
# omega within this fraction of its largest |omega| counts as zero: where the orbit only
# touches zero (the undeformed sphere at t = 0, omega = -sin^2 theta), rounding of the
# velocities decides its sign there (1e-13 of the largest seen).
ZERO = 1e-8


def angular_velocity(nodes, velocity):
    """(theta, omega) of the nodes within BAND of the shear plane through the centroid
    (nodes, velocity: (N, 3) arrays of one capsule)."""
    r = nodes - nodes.mean(axis=0)
    u = velocity - velocity.mean(axis=0)
    radius = np.sqrt((r**2).sum(axis=1)).mean()
    near = np.abs(r[:, 2]) < BAND * radius
    r, u = r[near], u[near]
    rho2 = r[:, 0] ** 2 + r[:, 1] ** 2
    return np.arctan2(r[:, 1], r[:, 0]), (r[:, 0] * u[:, 1] - r[:, 1] * u[:, 0]) / rho2


def fourier_design(theta, harmonics=HARMONICS):
    columns = [np.ones_like(theta)]
    for k in range(1, harmonics + 1):
        columns += [np.cos(k * theta), np.sin(k * theta)]
    return np.column_stack(columns)


def frequency(nodes, velocity):
    """The tank-treading frequency 2 pi / T of one capsule, over gammadot, positive
    (the membrane turns with the vorticity, clockwise in the shear plane of v = (y, 0,
    0)). NaN where omega changes sign on the orbit or reaches zero (no tank-treading: a
    swinging or tumbling capsule, or no steady state)."""
    theta, omega = angular_velocity(np.asarray(nodes, float), np.asarray(velocity, float))
    coef, *_ = np.linalg.lstsq(fourier_design(theta), omega, rcond=None)
    orbit = fourier_design(np.linspace(-np.pi, np.pi, GRID, endpoint=False)) @ coef
    zero = ZERO * np.max(np.abs(orbit))
    if np.any(orbit >= -zero) and np.any(orbit <= zero):
        return float("nan")
    return float(1.0 / np.mean(1.0 / np.abs(orbit)))


def run_frequency(run_dir, t_start=0.0):
    """The frequency of a one-capsule run from its last snapshot (NaN where the run has
    no snapshot with velocities at or after t_start: the steady state's window)."""
    try:
        snap = last_snapshot(run_dir)
    except FileNotFoundError:
        return float("nan")
    if "velocity" not in snap or snap.get("time", 0.0) < t_start:
        return float("nan")
    return frequency(snap["nodes"], snap["velocity"])


def marker_frequency(snapshots, t_start):
    """The tank-treading frequency from the nodes' own turns (snapshots: read_snapshot
    dicts of one capsule in time order, frequent enough that a node turns less than
    pi between two): for every node within BAND of the shear plane, 2 pi k over the
    time its angle about the centroid takes for its last whole k turns after t_start;
    the mean over the nodes. NaN where no node completes a turn."""
    t = np.array([s["time"] for s in snapshots])
    x = np.array([s["nodes"] for s in snapshots], dtype=float)
    r = x - x.mean(axis=1, keepdims=True)
    turned = -np.unwrap(np.arctan2(r[:, :, 1], r[:, :, 0]), axis=0)  # clockwise > 0
    radius = np.sqrt((r[-1] ** 2).sum(axis=1)).mean()
    rates = []
    for node in np.where(np.abs(r[-1, :, 2]) < BAND * radius)[0]:
        a = turned[:, node]
        a0 = np.interp(t_start, t, a)
        turns = int((a[-1] - a0) // (2 * np.pi))
        if turns >= 1:
            rates.append(2 * np.pi * turns / (np.interp(a0 + 2 * np.pi * turns, a, t) - t_start))
    return float(np.mean(rates)) if rates else float("nan")

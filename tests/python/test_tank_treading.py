"""The tank-treading frequency (analysis/tank_treading.py) from a snapshot's velocities:
a nearly rigid capsule turns at gammadot / 2 (a rigid sphere's rate), and at Ca 0.2 the
frequency equals the one measured from the nodes' own turns in frequent snapshots."""

import math

import numpy as np
import pytest

from analysis import snapshots, tank_treading


def test_a_nearly_rigid_capsule_turns_at_half_the_shear_rate(capsim_run):
    # Ca 0.02, level 2: measured 0.4980; the capsule's deformation and the mesh take
    # less than 1 % off a rigid sphere's 1/2.
    run = capsim_run("rigid", "ca=0.02", "mesh_level=2", "t_end=3", "t_avg_start=2",
                     "output.snapshot_interval=1.5")
    assert tank_treading.run_frequency(run) == pytest.approx(0.5, rel=0.01)
    # A last snapshot before the averaging window is not the steady state: none.
    assert math.isnan(tank_treading.run_frequency(run, t_start=4))
    # At t = 0 the sphere moves with the shear flow: no orbit, no frequency.
    first = snapshots.read_snapshot(snapshots.snapshot_files(run)[0])
    assert math.isnan(tank_treading.frequency(first["nodes"], first["velocity"]))


def test_an_orbit_that_only_touches_zero_has_no_frequency_whatever_the_rounding():
    # The sphere in the undisturbed shear flow: omega = -sin^2 theta reaches zero at
    # theta = 0 and pi, where velocities rounded by 1e-16 either way decide its sign.
    rng = np.random.default_rng(1)
    theta = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    nodes = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    for _ in range(20):
        velocity = np.column_stack([nodes[:, 1], np.zeros_like(theta),
                                    np.zeros_like(theta)])
        velocity += 1e-16 * rng.standard_normal(velocity.shape)
        assert math.isnan(tank_treading.frequency(nodes, velocity))
    # A tank-treading orbit, omega = -(1/2 + sin^2 theta / 4) < 0: its harmonic mean.
    omega = 0.5 + 0.25 * np.sin(theta) ** 2
    velocity = np.column_stack([omega * nodes[:, 1], -omega * nodes[:, 0],
                                np.zeros_like(theta)])
    grid = np.linspace(-np.pi, np.pi, tank_treading.GRID, endpoint=False)
    assert tank_treading.frequency(nodes, velocity) == pytest.approx(
        1 / np.mean(1 / (0.5 + 0.25 * np.sin(grid) ** 2)))


def test_the_velocity_frequency_is_the_nodes_turning_rate(capsim_run):
    # Ca 0.2, level 2, steady from gammadot t = 10; about 1.3 turns after it. Measured:
    # 0.3993 from the last snapshot's velocities, 0.3995 from the turns (0.3987 and
    # 0.3995 to t = 40, every node's turns within 6e-6 of their mean): within 0.2 %;
    # the tolerance 0.5 % leaves room for the fit's and the mesh's scatter.
    run = capsim_run("turns", "ca=0.2", "mesh_level=2", "t_end=30", "t_avg_start=10",
                     "output.snapshot_interval=0.1")
    frames = [snapshots.read_snapshot(f) for f in snapshots.snapshot_files(run)]
    turning = tank_treading.marker_frequency(frames, t_start=10)
    assert 0.35 < turning < 0.45
    assert tank_treading.run_frequency(run) == pytest.approx(turning, rel=0.005)

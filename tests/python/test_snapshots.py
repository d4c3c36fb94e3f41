"""analysis.snapshots: reading snapshot files and the sheared periodic images, against
values worked out by hand."""

import h5py
import numpy as np
import pytest

from analysis.snapshots import (image_offsets, last_snapshot, read_snapshot, strain_offset,
                                wrap_capsules)


def write_snapshot(path, nodes, time, **scalars):
    path.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(path, "w") as f:
        f["nodes"] = nodes
        f["triangles"] = np.array([[0, 1, 2]], dtype=np.int32)
        f["time"] = time
        for key, value in scalars.items():
            f[key] = value


def test_read_snapshot_and_the_last_one(tmp_path):
    nodes = np.arange(9.0).reshape(3, 3)
    write_snapshot(tmp_path / "snapshots" / "snapshot_000000.h5", nodes, 0.0)
    write_snapshot(tmp_path / "snapshots" / "snapshot_000001.h5", 2 * nodes, 1.5,
                   box_side=4.0, strain=-0.5, num_capsules=np.int32(1))
    first = read_snapshot(tmp_path / "snapshots" / "snapshot_000000.h5")
    assert set(first) == {"nodes", "triangles", "time"}  # an older file: no box or strain
    last = last_snapshot(tmp_path)
    assert last["time"] == 1.5 and last["box_side"] == 4.0 and last["strain"] == -0.5
    assert last["num_capsules"] == 1
    np.testing.assert_array_equal(last["nodes"], 2 * nodes)
    np.testing.assert_array_equal(last["triangles"], [[0, 1, 2]])
    with pytest.raises(FileNotFoundError):
        last_snapshot(tmp_path / "no-such-run")


@pytest.mark.parametrize("t, s", [(0.0, 0.0), (0.3, 0.3), (0.5, -0.5), (0.7, -0.3),
                                  (1.5, -0.5), (2.25, 0.25), (-0.6, 0.4)])
def test_strain_offset_wraps_into_minus_half_to_half(t, s):
    assert strain_offset(t) == pytest.approx(s, abs=1e-15)


def test_wrap_moves_a_capsule_by_a_sheared_layer():
    # L = 4, s = 1/4: a capsule whose centroid is at (0.5, 4.5, -3.5) is one layer up (y)
    # and one cell down (z). Moving it down one layer also moves it by -s L = -1 along x,
    # to x = -0.5, so x then wraps by L: the centroid lands at (3.5, 0.5, 0.5).
    side, s = 4.0, 0.25
    offsets = np.array([[0.1, 0.0, 0.0], [-0.1, 0.0, 0.0], [0.0, 0.2, 0.0], [0.0, -0.2, 0.0]])
    inside = np.array([1.0, 2.0, 3.0]) + offsets       # already in the box: not moved
    outside = np.array([0.5, 4.5, -3.5]) + offsets
    caps = wrap_capsules(np.concatenate([inside, outside]), 2, side, s)
    assert caps.shape == (2, 4, 3)
    np.testing.assert_allclose(caps[0], inside, atol=1e-15)
    np.testing.assert_allclose(caps[1], np.array([3.5, 0.5, 0.5]) + offsets, atol=1e-15)


def test_image_offsets_of_the_sheared_lattice():
    side, s = 2.0, 0.25
    xy = image_offsets(side, s, "xy")
    want = {(i * side + j * s * side, j * side, 0.0)
            for i in (-1, 0, 1) for j in (-1, 0, 1) if (i, j) != (0, 0)}
    assert {tuple(o) for o in xy} == want  # (0.5, 2, 0): the layer above, shifted by s L
    every = image_offsets(side, s, "all")
    assert len(every) == 26 and {tuple(o) for o in every if o[2] == 0} == want
    assert {o[2] for o in every} == {-side, 0.0, side}
    assert image_offsets(side, s, "none").shape == (0, 3)


"""The snapshot fields (capsule index, velocity, traction, principal tensions per node
and per element, area dilatation) as a third-party XDMF reader (meshio) sees them,
checked against what they must be: zero load on the undeformed spheres, no net membrane
force on a capsule, and node tensions that are the means of the element ones."""

import h5py
import meshio
import numpy as np
import pytest

CAPSULES, NODES = 2, 42  # mesh level 1: 42 nodes, 80 triangles per capsule


@pytest.fixture(scope="module")
def series(capsim_run):
    out = capsim_run("series", "mesh_level=1", "ca=0.3", "phi=0.2", f"capsules={CAPSULES}",
                     "t_end=0.5", "t_avg_start=0.25", "dt_safety=0.5",
                     "output.snapshot_interval=0.25")
    steps = []
    with meshio.xdmf.TimeSeriesReader(out / "snapshots.xdmf") as reader:
        _, cells = reader.read_points_cells()
        for k in range(reader.num_steps):
            steps.append(reader.read_data(k))
    return cells[0].data, steps, out


def lumped_areas(points, triangles):
    """A third of the area of every triangle at each of its nodes."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    nodal = np.zeros(len(points))
    for k in range(3):
        np.add.at(nodal, triangles[:, k], area / 3)
    return nodal


def test_fields_are_present_with_their_shapes(series):
    triangles, steps, _ = series
    assert len(steps) == 3  # t = 0, 0.25, 0.5 (to the step grid)
    for _, point_data, cell_data in steps:
        assert point_data["velocity"].shape == (CAPSULES * NODES, 3)
        assert point_data["traction"].shape == (CAPSULES * NODES, 3)
        assert point_data["tension_max"].shape == (CAPSULES * NODES,)
        assert np.array_equal(point_data["capsule"], np.repeat(np.arange(CAPSULES), NODES))
        assert cell_data["area_dilatation"][0].shape == (len(triangles),)
        assert cell_data["element_tension_max"][0].shape == (len(triangles),)
        assert cell_data["element_tension_min"][0].shape == (len(triangles),)
        assert np.all(np.isfinite(point_data["velocity"]))


def test_undeformed_spheres_carry_no_load(series):
    _, steps, _ = series
    _, point_data, cell_data = steps[0]
    assert np.abs(point_data["traction"]).max() < 1e-12
    assert np.abs(point_data["tension_max"]).max() < 1e-12
    assert np.abs(point_data["tension_min"]).max() < 1e-12
    assert np.allclose(cell_data["area_dilatation"][0], 1.0, rtol=0, atol=1e-12)
    assert np.abs(cell_data["element_tension_max"][0]).max() < 1e-12
    assert np.abs(cell_data["element_tension_min"][0]).max() < 1e-12


def test_deformed_capsules_carry_no_net_membrane_force(series):
    triangles, steps, out = series
    _, point_data, cell_data = steps[-1]
    with h5py.File(out / "snapshots" / "snapshot_000002.h5", "r") as f:
        points = f["/nodes"][()]
    q = point_data["traction"]
    force = q * lumped_areas(points, triangles)[:, None]  # lumped load: F_i = q_i A_i
    for c in range(CAPSULES):
        nodes = slice(c * NODES, (c + 1) * NODES)
        assert np.abs(force[nodes]).sum() > 1e-3  # the capsules are loaded by now
        assert np.linalg.norm(force[nodes].sum(axis=0)) < 1e-10 * np.abs(force[nodes]).sum()
    assert np.all(point_data["tension_max"] >= point_data["tension_min"])
    assert np.all(cell_data["area_dilatation"][0] > 0)


def test_node_tensions_are_the_means_of_the_element_tensions(series):
    """At a node, the mean of its elements' T1 (T2) weighted by their reference areas,
    which the first snapshot (the undeformed spheres) holds."""
    triangles, steps, out = series
    with h5py.File(out / "snapshots" / "snapshot_000000.h5", "r") as f:
        reference = f["/nodes"][()]
    a, b, c = (reference[triangles[:, k]] for k in range(3))
    weight = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    _, point_data, cell_data = steps[-1]
    for node_name, cell_name in (("tension_max", "element_tension_max"),
                                 ("tension_min", "element_tension_min")):
        element = cell_data[cell_name][0]
        total, weights = np.zeros(len(reference)), np.zeros(len(reference))
        for k in range(3):
            np.add.at(total, triangles[:, k], weight * element)
            np.add.at(weights, triangles[:, k], weight)
        assert np.allclose(point_data[node_name], total / weights, rtol=1e-12, atol=1e-12)
    assert np.all(cell_data["element_tension_max"][0] >= cell_data["element_tension_min"][0])

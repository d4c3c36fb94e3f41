"""Mesh snapshots of a run and the periodic images of its box (figure 2).

snapshots/snapshot_NNNNNN.h5 (solver/io/xdmf_snapshot.hpp) holds /nodes (N, 3) and
/triangles (T, 3) of all capsules together (capsule c's nodes start at c N / M), and the
scalars /time, /num_capsules, /box_side (L; 0 in the dilute limit) and /strain (the
Lees-Edwards offset of the lattice); snapshots of older runs lack the last three.

The sheared lattice (docs/conventions.md): the box [0, L)^3 repeats along x and z by L; the
layer above (y + L) is shifted along x by s L, s the strain gammadot t wrapped into
[-1/2, 1/2).
"""

import itertools
from pathlib import Path

import h5py
import numpy as np

SNAPSHOT_DIR = "snapshots"
SNAPSHOT_GLOB = "snapshot_*.h5"
SCALARS = ("time", "num_capsules", "box_side", "strain")


def snapshot_files(run_dir):
    """The run's snapshot files in the order they were written."""
    return sorted((Path(run_dir) / SNAPSHOT_DIR).glob(SNAPSHOT_GLOB))


def read_snapshot(path):
    """One snapshot file as a dict: "nodes" (N, 3), "triangles" (T, 3), "velocity"
    (N, 3) where the file holds it, and those of "time", "num_capsules", "box_side",
    "strain" the file holds (Python numbers)."""
    with h5py.File(path, "r") as f:
        out = {"nodes": f["nodes"][()], "triangles": f["triangles"][()]}
        if "velocity" in f:
            out["velocity"] = f["velocity"][()]
        out.update({k: f[k][()].item() for k in SCALARS if k in f})
    return out


def last_snapshot(run_dir):
    """The run's last snapshot (read_snapshot). FileNotFoundError if it wrote none."""
    files = snapshot_files(run_dir)
    if not files:
        raise FileNotFoundError(f"{run_dir} has no snapshots (set output.snapshot_interval > 0)")
    return read_snapshot(files[-1])


def strain_offset(t):
    """Lees-Edwards offset s = gammadot t wrapped into [-1/2, 1/2)."""
    return t - np.floor(t + 0.5)


def lattice_vectors(side, s):
    """Rows: the lattice vectors (L, 0, 0), (s L, L, 0), (0, 0, L) of the sheared lattice."""
    return np.array([[side, 0.0, 0.0], [s * side, side, 0.0], [0.0, 0.0, side]])


def wrap_capsules(nodes, capsules, side, s):
    """Nodes per capsule, shape (M, N / M, 3), each capsule moved by a lattice vector so
    that its centroid lies in [0, L)^3. The layer (y) goes first, because moving a capsule
    by one layer also moves it by s L along x; x and z are then wrapped by L."""
    caps = np.asarray(nodes, dtype=float).reshape(capsules, -1, 3)
    layer = np.floor(caps.mean(axis=1)[:, 1] / side)
    caps = caps - layer[:, None, None] * lattice_vectors(side, s)[1]
    cell = np.floor(caps.mean(axis=1) / side) * np.array([1.0, 0.0, 1.0])
    return caps - cell[:, None, :] * side


def image_offsets(side, s, mode):
    """Offsets (n, 3) of the periodic images of the box: "xy" the 8 neighbours in the shear
    plane, "all" the 26 around it (also the layers along z), "none" no image."""
    if mode == "none":
        return np.zeros((0, 3))
    along_z = [-1, 0, 1] if mode == "all" else [0]
    cells = [c for c in itertools.product([-1, 0, 1], [-1, 0, 1], along_z) if c != (0, 0, 0)]
    return np.array(cells, dtype=float) @ lattice_vectors(side, s)

"""Figure 2: snapshots of the suspension for each volume fraction (paper: Ca = 0.3,
phi = 0.1-0.4): the capsules of the original box (bright) and their periodic images (dark),
which move with the shear (Lees-Edwards: the images above and below are shifted along x by
the strain offset s L, s = gammadot t wrapped into [-1/2, 1/2)).

Usage: python figures/fig02.py --out results/figures/fig02 [--images xy|all|none] RUN/summary.json ...
Reads each run's last snapshot (analysis.snapshots).
"""

import itertools
import math
from pathlib import Path

import numpy as np
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

import common
from analysis.read_run import read_summary
from analysis.rheology import box_side
from analysis.snapshots import image_offsets, last_snapshot, strain_offset, wrap_capsules


def cube_edges(side):
    corners = np.array(list(itertools.product([0, side], repeat=3)))
    return [(a, b) for a, b in itertools.combinations(corners, 2)
            if np.count_nonzero(a != b) == 1]


def draw(ax, run, mode):
    summary = read_summary(run)
    p = summary["parameters"]
    capsules, phi = int(p["capsules"]), float(p["phi"])
    try:
        frame = last_snapshot(run)
    except FileNotFoundError as e:
        raise SystemExit(f"fig02: {e}")
    nodes, tris = frame["nodes"], frame["triangles"]
    # The snapshot records the box and the lattice strain; older runs' files do not.
    side = frame.get("box_side") or summary.get("box_side") or box_side(capsules, phi)
    s = frame.get("strain", strain_offset(frame["time"]))
    caps = wrap_capsules(nodes, capsules, side, s)
    per = tris[: len(tris) // capsules] % (len(nodes) // capsules)
    faces = np.concatenate([c[per] for c in caps])
    # The surfaces are drawn as an image in the PDF too (at savefig.dpi): as vectors they
    # are a million triangles, a PDF of 16 MB that took most of the figure's minutes.
    for off in image_offsets(side, s, mode):
        ax.add_collection3d(Poly3DCollection(faces + off, facecolor="0.35", edgecolor="none",
                                             alpha=0.35, rasterized=True))
    ax.add_collection3d(Poly3DCollection(faces, facecolor="#f4c27a", edgecolor="0.3",
                                         linewidth=0.05, rasterized=True))
    ax.add_collection3d(Line3DCollection(cube_edges(side), colors="k", linewidths=0.8))
    reach = side * (2.0 if mode != "none" else 1.0)
    lo = -side if mode != "none" else 0
    ax.set(xlim=(lo, lo + reach + side * (mode != "none")), ylim=(lo, lo + reach + side * (mode != "none")),
           zlim=(lo if mode == "all" else 0, side * (2 if mode == "all" else 1)))
    ax.set_box_aspect((1, 1, 1 if mode == "all" else 1 / 3 if mode == "xy" else 1))
    ax.view_init(elev=25, azim=-60)
    ax.set_axis_off()
    return {"ca": float(p["ca"]), "phi": phi, "capsules": capsules, "time": frame["time"],
            "strain_offset": s, "box_side": side, "mesh_level": int(p["mesh_level"]),
            "run": str(run)}


def main(args):
    runs = [Path(p).parent if p.endswith(".json") else Path(p) for p in args.inputs]
    runs.sort(key=lambda r: float(read_summary(r)["parameters"]["phi"]))
    cols = 2 if len(runs) > 1 else 1
    rows_n = math.ceil(len(runs) / cols)
    fig = common.plt.figure(figsize=(3.4 * cols, 3.2 * rows_n))
    data = []
    for i, run in enumerate(runs):
        ax = fig.add_subplot(rows_n, cols, i + 1, projection="3d")
        info = draw(ax, run, args.images)
        ax.set_title(f"({'abcdefgh'[i]}) phi = {info['phi']:g}")
        data.append(info)
    d = data[0]
    times = ", ".join(f"{r['time']:.3g}" for r in data)
    caption = (f"Figure 2. Snapshots at the last stored time (gammadot t = {times}), Ca = {d['ca']:g}; bright: "
               f"the original box, dark: periodic images ({args.images}), shifted by the shear. "
               f"Runs: N_E = {common.elements(d['mesh_level'])}; M = {d['capsules']}.")
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

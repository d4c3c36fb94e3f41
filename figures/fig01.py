"""Figure 1: error of the multipole expansion (eq. 3.11, mean over the flow, vorticity and
gradient directions) against the distance r/a from the capsule centre, for each number of
patches P; one panel per Ca (paper: (a) Ca = 0.1, (b) 0.5). A 1/r guide shows the slope.

Usage: python figures/fig01.py --out results/figures/fig01 results/multipole/ca0.1_level4.csv ...
(each table names its capsule's Ca and mesh level in its columns ca, mesh_level)
"""

import numpy as np
import pandas as pd

import common
from analysis.tables import read_table

ERRORS = ["error_mean", "error_flow", "error_vorticity", "error_gradient"]


def main(args):
    tables = []
    for path in args.inputs:
        rows = read_table(path)
        named = {"ca", "mesh_level"} <= set(rows)
        if not named or rows[["ca", "mesh_level"]].nunique().max() != 1:
            raise SystemExit(f"fig01: {path} names no single capsule (columns ca, mesh_level: "
                             "capsim multipole-error writes them)")
        tables.append((float(rows["ca"].iloc[0]), int(rows["mesh_level"].iloc[0]), rows))
    tables.sort(key=lambda t: t[:2])
    fig, axes = common.plt.subplots(1, len(tables), figsize=(3.5 * len(tables), 3.0),
                                    squeeze=False)
    data = []
    for ax, (ca, level, rows), letter in zip(axes[0], tables, "abcdefgh"):
        rows = rows.astype({"patches": int})
        col = common.colors(rows["patches"].unique())
        for p, sel in rows.sort_values("r_over_a", kind="stable").groupby("patches"):
            ax.loglog(sel["r_over_a"], sel["error_mean"], "o-", color=col[p], label=f"P = {p}")
            data.append(sel[["r_over_a"] + ERRORS].assign(panel=letter, ca=ca,
                                                          mesh_level=level, patches=p))
        ax.axhline(1e-2, color="0.6", lw=0.8, ls=":")
        r0 = np.array([rows["r_over_a"].min(), rows["r_over_a"].max()])
        ax.loglog(r0, 0.5 * r0[0] / r0 * rows["error_mean"].max(), "k--", lw=0.8,
                  label=r"$\propto (r/a)^{-1}$")
        ax.set(xlabel="r/a", ylabel=r"$\varepsilon$", title=f"({letter}) Ca = {ca:g}")
        ax.legend()
    fig.tight_layout()
    levels = sorted({t[1] for t in tables})
    caption = ("Figure 1. Relative error of the P-patch multipole expansion against fine "
               "quadrature (eq. 3.11), mean of the three directions; dotted: 1e-2. Capsule: "
               f"the dilute run's last checkpoint, N_E = {', '.join(str(common.elements(l)) for l in levels)}.")
    columns = ["panel", "ca", "mesh_level", "patches", "r_over_a"] + ERRORS
    common.save(fig, args.out, pd.concat(data)[columns], caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

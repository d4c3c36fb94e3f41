"""The viscosity-ratio study: one capsule in unbounded shear, D, theta_D, the intrinsic
viscosity [mu] and the tank-treading frequency against Ca, one line per viscosity ratio lambda (the paper's lambda = 1
among them). Runs that stopped before their end are not drawn: the caption lists them,
with when and how they stopped.

Usage: python figures/viscosity_ratio.py --out results/figures/viscosity_ratio \
           results/viscosity_ratio/table.csv
Writes STEM.png, STEM.pdf and the plotted data STEM.csv.
"""

import numpy as np

import common
from common import plt

from analysis.viscosity_ratio import SE

PANELS = (("D", "D"), ("theta_D_deg", r"$\theta_D$ (deg)"), ("mu_sp", r"$[\mu]$"),
          ("tank_treading", r"$\omega_{tt} / \dot\gamma$"))
NO_ERROR = ("tank_treading",)  # one snapshot: no standard error
MARKERS = ("o", "s", "D", "^", "v", "P", "X")


def series_label(ratio):
    return rf"$\lambda$ = {ratio:g}" + (" (paper)" if ratio == 1 else "")


def stopped_text(rows, by="ca", hollow=None):
    """The runs that stopped before their end: their Ca (or, by="phi", phi), lambda, how
    and when they stopped; those of the mask `hollow` drawn hollow, the others not
    drawn."""
    early = rows["ended"] != "t_end"
    if not early.any():
        return "Every run reached its end."
    hollow = common.pd.Series(False, rows.index) if hollow is None else hollow
    name = {"ca": "Ca", "phi": "phi"}[by]

    def items(mask):
        # records, not itertuples: "lambda" is a Python keyword, no attribute name
        return "; ".join(f"{name} {r[by]:g}, lambda {r['lambda']:g}: {r['ended']} at "
                         f"gammadot t = {r['t_stop']:.3g}"
                         for r in rows[mask].to_dict("records"))

    parts = []
    if (early & hollow).any():
        parts.append("Drawn hollow, stopped before their end and averaged to their stop: "
                     + items(early & hollow) + ".")
    if (early & ~hollow).any():
        parts.append("Not drawn, stopped before their end: " + items(early & ~hollow) + ".")
    return " ".join(parts)


def draw_ratios(table, x, xlabel, panels, no_error=(), hollow=None):
    """One panel per (quantity, label) of `panels` against column x, one line per
    lambda, of the runs that reached their end and those of the mask `hollow` (with
    hollow markers; error bars but for `no_error`). Returns the figure and the rows
    drawn."""
    hollow = common.pd.Series(False, table.index) if hollow is None else hollow
    drawn = table[(table["ended"] == "t_end") | hollow]
    ratios = sorted(set(table["lambda"]))
    colors = common.colors(ratios)
    fig, axes = plt.subplots(1, len(panels), figsize=(10, 2.6))
    plotted = []
    for i, ratio in enumerate(ratios):
        rows = drawn[drawn["lambda"] == ratio].sort_values(x)
        if rows.empty:
            continue
        marker = MARKERS[i % len(MARKERS)]
        for ax, (q, _) in zip(axes, panels):
            error = None if q in no_error else rows[SE.get(q, f"{q}_se")]
            line = common.points(ax, rows[x], rows[q], yerr=error, fmt=marker + "-",
                                 color=colors[ratio], label=series_label(ratio)).lines[0]
            early = hollow[rows.index].to_numpy()
            if early.any():  # the filled markers only where the run reached its end
                line.set_markevery(list(np.flatnonzero(~early)))
                ax.plot(rows[x][early], rows[q][early], marker, color=colors[ratio],
                        markerfacecolor="white")
        plotted.append(rows)
    for ax, (_, label) in zip(axes, panels):
        ax.set(xlabel=xlabel, ylabel=label)
    if axes[0].get_legend_handles_labels()[0]:
        axes[-1].legend(fontsize=7)
    return fig, plotted


def main():
    out, table = common.parse_table_args(__doc__.splitlines()[0])
    table["ended"] = table["ended"].fillna("t_end")
    finished = table[table["ended"] == "t_end"]
    fig, plotted = draw_ratios(table, "ca", "Ca", PANELS, NO_ERROR)
    fig.tight_layout()
    caption = ("One capsule in unbounded shear with interior viscosity lambda times the "
               "suspending fluid's (docs/workflow.md, the viscosity-ratio study); the paper "
               "has lambda = 1 only, the other lines are beyond it. [mu]: the intrinsic "
               "viscosity, mu_sp / phi as phi -> 0. omega_tt: the tank-treading frequency "
               "from the last snapshot (analysis/tank_treading.py). "
               + stopped_text(table) + " "
               + common.ERROR_BARS + ". "
               + common.footer(finished if not finished.empty else table))
    data = common.pd.concat(plotted, ignore_index=True) if plotted else table.iloc[:0]
    columns = ["ca", "lambda", "mesh_level", "N_E", "ended"]
    columns += [c for q, _ in PANELS
                for c in ((q,) if q in NO_ERROR else (q, SE.get(q, f"{q}_se")))]
    common.save(fig, out, data[columns], caption)


if __name__ == "__main__":
    main()

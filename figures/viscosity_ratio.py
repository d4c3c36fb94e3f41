"""The viscosity-ratio study: one capsule in unbounded shear, D, theta_D, the intrinsic
viscosity [mu] and the tank-treading frequency against Ca, one line per viscosity ratio lambda (the paper's lambda = 1
among them). Runs that stopped before their end are not drawn: the caption lists them,
with when and how they stopped.

Usage: python figures/viscosity_ratio.py --out results/figures/viscosity_ratio \
           results/viscosity_ratio/table.csv
Writes STEM.png, STEM.pdf and the plotted data STEM.csv.
"""

import common
from common import plt

from analysis.viscosity_ratio import SE

PANELS = (("D", "D"), ("theta_D_deg", r"$\theta_D$ (deg)"), ("mu_sp", r"$[\mu]$"),
          ("tank_treading", r"$\omega_{tt} / \dot\gamma$"))
NO_ERROR = ("tank_treading",)  # one snapshot: no standard error
MARKERS = ("o", "s", "D", "^", "v", "P", "X")


def series_label(ratio):
    return rf"$\lambda$ = {ratio:g}" + (" (paper)" if ratio == 1 else "")


def stopped_text(rows, by="ca"):
    """The runs not drawn: their Ca (or, by="phi", phi), lambda, how and when they
    stopped."""
    early = rows[rows["ended"] != "t_end"]
    if early.empty:
        return "Every run reached its end."
    name = {"ca": "Ca", "phi": "phi"}[by]
    # records, not itertuples: "lambda" is a Python keyword, no attribute name
    items = [f"{name} {r[by]:g}, lambda {r['lambda']:g}: {r['ended']} at gammadot t = "
             f"{r['t_stop']:.3g}" for r in early.to_dict("records")]
    return "Not drawn, stopped before their end: " + "; ".join(items) + "."


def draw_ratios(table, x, xlabel, panels, no_error=()):
    """One panel per (quantity, label) of `panels` against column x, one line per
    lambda, of the runs that reached their end (with error bars but for `no_error`).
    Returns the figure and the rows drawn."""
    finished = table[table["ended"] == "t_end"]
    ratios = sorted(set(table["lambda"]))
    colors = common.colors(ratios)
    fig, axes = plt.subplots(1, len(panels), figsize=(10, 2.6))
    plotted = []
    for i, ratio in enumerate(ratios):
        rows = finished[finished["lambda"] == ratio].sort_values(x)
        if rows.empty:
            continue
        for ax, (q, _) in zip(axes, panels):
            error = None if q in no_error else rows[SE.get(q, f"{q}_se")]
            common.points(ax, rows[x], rows[q], yerr=error,
                          fmt=MARKERS[i % len(MARKERS)] + "-", color=colors[ratio],
                          label=series_label(ratio))
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

"""Speed against error: the total relative error of <D> and mu_sp of every setting of the
accuracy study against its CPU seconds per unit strain, one row of panels per case, the
Pareto front drawn as a line and the configurations' settings marked.

Usage: python figures/speed_error.py --out results/figures/speed_error \
           results/accuracy/errors.csv
Writes STEM.png, STEM.pdf and the plotted data STEM.csv.
"""


import common
from common import plt
from matplotlib.ticker import FormatStrFormatter, LogLocator

from analysis.accuracy import PARTS

QUANTITIES = {"D": "<D>", "mu_sp": "mu_sp"}
FAMILIES = {"base": "*", "mesh": "o", "ewald": "s", "time": "^", "capsules": "D",
            "window": "v"}


def panel(ax, rows, q):
    """One case and quantity: the points by family, the front, the configurations."""
    for family, group in rows.groupby("family", sort=False):
        configured = family not in FAMILIES
        color = f"C{list(FAMILIES).index(family)}" if not configured else "C6"
        ax.loglog(group["cpu_s_per_strain"], group[f"{q}_total"],
                  FAMILIES.get(family, "P"), color=color, ms=9 if configured else 5,
                  mfc="none" if configured else None,
                  label=f"configuration '{family}'" if configured else family)
    front = rows[rows[f"{q}_pareto"]].sort_values("cpu_s_per_strain")
    ax.plot(front["cpu_s_per_strain"], front[f"{q}_total"], "k-", lw=0.8,
            label="Pareto front")
    ax.set_xlabel("CPU s per unit strain")
    ax.set_ylabel(f"relative error of {QUANTITIES[q]}")
    for axis in (ax.xaxis, ax.yaxis):  # ranges within a decade: label 1, 2, 5 of each
        axis.set_major_formatter(FormatStrFormatter("%g"))
        axis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
        axis.set_minor_formatter(FormatStrFormatter("%g"))


def main():
    out, table = common.parse_table_args(__doc__.splitlines()[0])
    cases = list(dict.fromkeys(table["case"]))
    fig, axes = plt.subplots(len(cases), len(QUANTITIES), squeeze=False,
                             figsize=(7.0, 2.8 * len(cases)))
    for row_axes, case in zip(axes, cases):
        rows = table[table["case"] == case]
        for ax, q in zip(row_axes, QUANTITIES):
            panel(ax, rows, q)
            ax.set_title(case.replace("_", " "), fontsize=8)
    axes[0][0].legend(fontsize=6)
    fig.tight_layout()
    columns = (["case", "family", "families", "label", "cpu_s_per_strain", "wall_s"] +
               [f"{q}_{part}" for q in QUANTITIES for part in PARTS + ("total", "pareto")])
    caption = ("Each point changes one setting of the base run (family); its error is the "
               "root sum of squares of the discretisation, Ewald, time-step and statistical "
               "parts, each measured on its own (docs/workflow.md, accuracy study). "
               "Observed mesh orders: " + "; ".join(
                   f"{case}: D {table.loc[table['case'] == case, 'D_order'].iloc[0]:.2f}"
                   for case in cases) + ".")
    common.save(fig, out, table[columns], caption)


if __name__ == "__main__":
    main()

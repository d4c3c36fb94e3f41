"""The viscosity-ratio study's suspensions: <D>, theta_D, mu_sp and N1 against phi at the
Table 1 point's Ca, one line per viscosity ratio lambda (lambda = 1: the grid's runs, the
paper's suspension). A run that stopped before its end is drawn hollow, averaged to its
stop, where its window holds at least half the planned one (MIN_WINDOW, as the bending
limit asks of its runs), and is not drawn otherwise: the caption lists them, with when
and how they stopped.

Usage: python figures/viscosity_ratio_dense.py --out results/figures/viscosity_ratio_dense \
           results/viscosity_ratio/dense.csv
Writes STEM.png, STEM.pdf and the plotted data STEM.csv.
"""

import common
from viscosity_ratio import draw_ratios, stopped_text

from analysis.bending_limit import MIN_WINDOW
from analysis.viscosity_ratio import SE

PANELS = (("D", r"$\langle D \rangle$"), ("theta_D_deg", r"$\theta_D$ (deg)"),
          ("mu_sp", r"$\mu_{sp}$"), ("N1", "$N_1$"))


def main():
    out, table = common.parse_table_args(__doc__.splitlines()[0])
    table["ended"] = table["ended"].fillna("t_end")
    finished = table[table["ended"] == "t_end"]
    hollow = (table["ended"] != "t_end") & (table["count"] > 0) & (
        table["t_stop"] - table["t_start"]
        >= MIN_WINDOW * (table["t_planned"] - table["t_start"]))
    fig, plotted = draw_ratios(table, "phi", r"$\phi$", PANELS, hollow=hollow)
    fig.tight_layout()
    caption = ("The suspension of the Table 1 point's Ca in the sheared periodic box with "
               "interior viscosity lambda times the suspending fluid's (docs/workflow.md, "
               "the viscosity-ratio study); lambda = 1 is the paper's, the other lines are "
               "beyond it. " + stopped_text(table, by="phi", hollow=hollow) + " "
               + common.ERROR_BARS + ". "
               + common.footer(finished if not finished.empty else table))
    data = common.pd.concat(plotted, ignore_index=True) if plotted else table.iloc[:0]
    columns = ["ca", "phi", "lambda", "capsules", "mesh_level", "N_E", "ended"]
    columns += [c for q, _ in PANELS for c in (q, SE.get(q, f"{q}_se"))]
    common.save(fig, out, data[columns], caption)


if __name__ == "__main__":
    main()

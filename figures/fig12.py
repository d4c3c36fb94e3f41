"""Figure 12: effect of the number of capsules per box M on <D> and mu_sp; error bars: the
standard deviation of the cases with different initial positions (seeds, thin with caps,
the paper's) and the standard error of their mean (thick).

Usage: python figures/fig12.py --out results/figures/fig12 results/boxsize/table.csv
"""

import pandas as pd

import common
from analysis.statistics import mean_of_runs_standard_error
from analysis.tables import read_table, with_data


def main(args):
    rows = with_data(read_table(args.inputs[0]))
    rows = rows[rows["intrinsic"] == 0]
    by_m = rows.groupby("capsules")
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    for ax, key, label in ((ax_a, "D", r"$\langle D\rangle$"), (ax_b, "mu_sp", r"$\mu_{sp}$")):
        # ddof = 0: the standard deviation of the cases, as the paper's (appendix A.3); se:
        # that of the mean of the independent cases, sqrt(sum se_i^2) / n.
        stats = by_m.agg(mean=(key, "mean"), std=(key, lambda v: v.std(ddof=0)),
                         se=(key + "_se", mean_of_runs_standard_error), cases=(key, "count"))
        ax.errorbar(stats.index, stats["mean"], yerr=stats["std"], fmt="o", capsize=3)
        common.points(ax, stats.index, stats["mean"], stats["se"], fmt="none", color="C0",
                      capsize=0, elinewidth=3, alpha=0.5)
        ax.set(xlabel="M", ylabel=label)
        data.append(stats.reset_index().assign(quantity=key))
    ax_a.set_title("(a)")
    ax_b.set_title("(b)")
    fig.tight_layout()
    data = pd.concat(data)[["quantity", "capsules", "mean", "std", "se", "cases"]]
    r = rows.iloc[0]
    caption = (f"Figure 12. Mean and standard deviation over initial positions against M; "
               f"Ca = {r['ca']:g}, phi = {r['phi']:g}. Thin bars with caps: the standard "
               "deviation of the cases (the paper's); thick bars: the standard error of their "
               "mean, sqrt(sum se_i^2) / n, with se_i each run's standard error of the time "
               "average, from the integrated autocorrelation time (docs/conventions.md). "
               + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

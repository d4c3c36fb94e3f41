"""Figure 12: effect of the number of capsules per box M on <D> and mu_sp; error bars: the
standard deviation of the cases with different initial positions (seeds).

Usage: python figures/fig12.py --out results/figures/fig12 results/boxsize/table.csv
"""

import pandas as pd

import common
from analysis.tables import read_table, with_data


def main(args):
    rows = with_data(read_table(args.inputs[0]))
    rows = rows[rows["intrinsic"] == 0]
    by_m = rows.groupby("capsules")
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    for ax, key, label in ((ax_a, "D", r"$\langle D\rangle$"), (ax_b, "mu_sp", r"$\mu_{sp}$")):
        # ddof = 0: the standard deviation of the cases, as the paper's (appendix A.3).
        stats = by_m[key].agg(mean="mean", std=lambda v: v.std(ddof=0), cases="count")
        ax.errorbar(stats.index, stats["mean"], yerr=stats["std"], fmt="o", capsize=3)
        ax.set(xlabel="M", ylabel=label)
        data.append(stats.reset_index().assign(quantity=key))
    ax_a.set_title("(a)")
    ax_b.set_title("(b)")
    fig.tight_layout()
    data = pd.concat(data)[["quantity", "capsules", "mean", "std", "cases"]]
    r = rows.iloc[0]
    caption = (f"Figure 12. Mean and standard deviation over initial positions against M; "
               f"Ca = {r['ca']:g}, phi = {r['phi']:g}. " + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

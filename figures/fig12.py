"""Figure 12: effect of the number of capsules per box M on <D> and mu_sp; error bars: the
standard deviation of the cases with different initial positions (seeds).

Usage: python figures/fig12.py --out results/figures/fig12 results/boxsize/table.csv
"""

import common
from analysis.averages import ensemble
from analysis.tables import read_table, with_data


def main(args):
    rows = [r for r in with_data(read_table(args.inputs[0])) if not r["intrinsic"]]
    by_m = {}
    for r in rows:
        by_m.setdefault(int(r["capsules"]), []).append(r)
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    ms = sorted(by_m)
    for ax, key, label in ((ax_a, "D", r"$\langle D\rangle$"), (ax_b, "mu_sp", r"$\mu_{sp}$")):
        stats = [ensemble([r[key] for r in by_m[m]]) for m in ms]
        ax.errorbar(ms, [s[0] for s in stats], yerr=[s[1] for s in stats], fmt="o", capsize=3)
        ax.set(xlabel="M", ylabel=label)
        for m, (mean, std) in zip(ms, stats):
            data.append({"quantity": key, "capsules": m, "mean": mean, "std": std,
                         "cases": len(by_m[m])})
    ax_a.set_title("(a)")
    ax_b.set_title("(b)")
    fig.tight_layout()
    r = rows[0]
    caption = (f"Figure 12. Mean and standard deviation over initial positions against M; "
               f"Ca = {r['ca']:g}, phi = {r['phi']:g}. " + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

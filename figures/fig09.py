"""Figure 9: (a) <S12> against 1/2 <S1 - S2> sin 2<theta_S> (eq. 4.14) and (b) <S11 - S22>
against <S1 - S2> cos 2<theta_S> (eq. 4.15), filled symbols the dilute limit;
(c) <S1 - S2> against <D>; (d) <theta_D> against <theta_S>. Stresslets in Gs a^2. Bars
(both directions): the standard errors of the time averages.

Usage: python figures/fig09.py --out results/figures/fig09 results/grid/table.csv
"""

import common

# The standard-error column of each plotted quantity.
SE = {"S12_principal": "S12_principal_se", "S12": "S12_se",
      "S11_S22_principal": "S11_S22_principal_se", "S11_S22": "S11_S22_se", "D": "D_se",
      "principal_diff": "principal_diff_se", "theta_S_deg": "theta_S_se_deg",
      "theta_D_deg": "theta_D_se_deg"}
PANELS = [("S12_principal", "S12", r"$\frac{1}{2}\langle S_1-S_2\rangle\sin 2\langle\theta_S\rangle$",
           r"$\langle S_{12}\rangle$", True),
          ("S11_S22_principal", "S11_S22", r"$\langle S_1-S_2\rangle\cos 2\langle\theta_S\rangle$",
           r"$\langle S_{11}-S_{22}\rangle$", True),
          ("D", "principal_diff", r"$\langle D\rangle$", r"$\langle S_1-S_2\rangle$", False),
          ("theta_S_deg", "theta_D_deg", r"$\langle\theta_S\rangle$ (deg)",
           r"$\langle\theta_D\rangle$ (deg)", True)]


def main(args):
    rows, dilute, susp = common.grid_rows(args.inputs[0])
    col = common.colors(susp)
    fig, axes = common.plt.subplots(2, 2, figsize=(7.0, 6.0))
    for ax, (xkey, ykey, xlabel, ylabel, diagonal) in zip(axes.flat, PANELS):
        for ca, runs in sorted(susp.items()):
            common.points(ax, runs[xkey], runs[ykey], runs[SE[ykey]], runs[SE[xkey]],
                          fmt="o-", mfc="none", color=col[ca], label=f"Ca = {ca:g}")
            if ca in dilute:
                d = dilute[ca]
                common.points(ax, d[xkey], d[ykey], d[SE[ykey]], d[SE[xkey]], color=col[ca])
        if diagonal:
            lim = [rows[[xkey, ykey]].min().min(), rows[[xkey, ykey]].max().max()]
            ax.plot(lim, lim, "k:", lw=0.8)
        ax.set(xlabel=xlabel, ylabel=ylabel)
    for ax, label in zip(axes.flat, "abcd"):
        ax.set_title(f"({label})")
    axes[0, 0].legend()
    data = rows[["ca", "phi"]].assign(
        dilute=rows["intrinsic"].astype(int),
        **{c: rows[c] for k in ("S12", "S12_principal", "S11_S22", "S11_S22_principal", "D",
                                "principal_diff", "theta_D_deg", "theta_S_deg")
           for c in (k, SE[k])},
        eq_4_14_ratio=rows["S12"] / rows["S12_principal"],
        eq_4_15_ratio=rows["S11_S22"] / rows["S11_S22_principal"])
    fig.tight_layout()
    caption = ("Figure 9. Left- and right-hand sides of eqs. 4.14 and 4.15 (filled: dilute "
               "limit; open: phi > 0, joined in order of phi); stresslets in Gs a^2. "
               + common.ERROR_BARS + " (both directions; those of the right-hand sides by "
               "the delta method). " + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

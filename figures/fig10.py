"""Figure 10: relative to the dilute limit (superscript sol): (a) <S12> with 1 + (a2/a1) phi,
(b) <S11 - S22> with 1 + (b2/b1) phi, (c) <S1 - S2>, (d) sin 2<theta_S>, (e) cos 2<theta_S>,
against phi for each Ca. Bars: standard errors of the ratios, from those of the time
averages of the suspension and of the dilute run.

Usage: python figures/fig10.py --out results/figures/fig10 results/grid/table.csv
       results/grid/fits.csv
"""

import numpy as np

import common
from analysis import coefficients
from analysis.statistics import propagated_standard_error

PANELS = [("S12", r"$\langle S_{12}\rangle/S_{12}^{sol}$", "mu_sp"),
          ("S11_S22", r"$\langle S_{11}-S_{22}\rangle/(S_{11}-S_{22})^{sol}$", "N1"),
          ("principal_diff", r"$\langle S_1-S_2\rangle/(S_1-S_2)^{sol}$", None),
          ("sin2theta_S", r"$\sin 2\langle\theta_S\rangle/\sin 2\theta_S^{sol}$", None),
          ("cos2theta_S", r"$\cos 2\langle\theta_S\rangle/\cos 2\theta_S^{sol}$", None)]


def main(args):
    rows, dilute, susp = common.grid_rows(args.inputs[0])
    coefs = {key: coefficients.read_coefficients(args.inputs[1], key)[0]
             for key in coefficients.NAMES}
    col = common.colors(susp)
    fig, axes = common.plt.subplots(2, 3, figsize=(9.0, 5.6))
    axes.flat[-1].axis("off")
    data = []
    smooth = np.linspace(0, rows["phi"].max(), 40)
    for ax, (key, label, coef_key), letter in zip(axes.flat, PANELS, "abcde"):
        coef = coefs.get(coef_key, {})
        for ca, runs in sorted(susp.items()):
            if ca not in dilute:
                continue
            phi, y = common.phi_with_dilute(dilute[ca], runs, key)
            sol, sol_se = dilute[ca][key], dilute[ca][key + "_se"]
            ratio = y / sol
            # phi = 0 is the dilute run itself: its ratio is 1 exactly.
            se = [0.0] + [propagated_standard_error(lambda x: x[0] / x[1], [value, sol],
                                                    [error, sol_se])
                          for value, error in zip(runs[key], runs[key + "_se"])]
            common.points(ax, phi, ratio, se, fmt="o-", color=col[ca], label=f"Ca = {ca:g}")
            if ca in coef:
                c1, c2 = coef[ca]
                ax.plot(smooth, 1 + c2 / c1 * smooth, ":", color="0.5")
            data += [{"panel": letter, "quantity": key, "ca": ca, "phi": p, "ratio": v,
                      "ratio_se": e} for p, v, e in zip(phi, ratio, se)]
        ax.set(xlabel=r"$\phi$", ylabel=label, title=f"({letter})")
    axes[0, 0].legend()
    fig.tight_layout()
    caption = ("Figure 10. Stresslet quantities over their dilute-limit values; grey dotted: "
               "1 + (a2/a1) phi in (a), 1 + (b2/b1) phi in (b). " + common.ERROR_BARS
               + ", of the suspension and the dilute run, propagated to the ratio. "
               + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

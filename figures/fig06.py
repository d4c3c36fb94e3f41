"""Figure 6: ratios of (a) a1 phi and (b) a1 phi + a2 phi^2 to mu_sp against phi for each
Ca, with the rigid-sphere (Krieger-Dougherty) ratios; 1 - (b) is the O(phi^3) share.

Usage: python figures/fig06.py --out results/figures/fig06 results/grid/table.csv
"""

import numpy as np

import common
from analysis import fits


def share_figure(args, key, names, number, rigid):
    rows, dilute, susp = common.grid_rows(args.inputs[0])
    coef = common.coefficients(dilute, susp, key, args.fit_phi_max)
    col = common.colors(coef)
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    for ca, (c1, c2) in sorted(coef.items()):
        phi, y = susp[ca]["phi"].to_numpy(), susp[ca][key].to_numpy()
        first, second, higher = fits.order_shares(phi, y, c1, c2)
        ax_a.plot(phi, first, "o-", color=col[ca], label=f"Ca = {ca:g}")
        ax_b.plot(phi, second, "o-", color=col[ca], label=f"Ca = {ca:g}")
        data += [{"ca": ca, "phi": p, "first_share": f, "second_share": s,
                  "higher_share": h} for p, f, s, h in zip(phi, first, second, higher)]
    if rigid:
        phi = np.linspace(0.01, rows["phi"].max(), 40)
        a1, a2 = fits.kd_coefficients(2, args.phi_m)
        first, second, higher = fits.order_shares(phi, fits.kd_specific_viscosity(phi, args.phi_m), a1, a2)
        ax_a.plot(phi, first, "k-", label="rigid spheres (KD)")
        ax_b.plot(phi, second, "k-", label="rigid spheres (KD)")
        for p in (0.2, 0.4):
            f, s, h = fits.order_shares(np.array([p]), fits.kd_specific_viscosity(np.array([p]), args.phi_m), a1, a2)
            data.append({"ca": 0.0, "series": "krieger-dougherty", "phi": p,
                         "first_share": f[0], "second_share": s[0], "higher_share": h[0]})
    ax_a.set(xlabel=r"$\phi$", ylabel=names[0], title="(a)", ylim=(0, 1.1))
    ax_b.set(xlabel=r"$\phi$", ylabel=names[1], title="(b)", ylim=(0, 1.1))
    ax_a.legend()
    caption = (f"Figure {number}. Ratios {names[0]} and {names[1]}; the O(phi^3) share is "
               f"1 - (b). Fitting range 0 <= phi <= {args.fit_phi_max:g}. "
               + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    share_figure(common.parse_args(__doc__.splitlines()[0]), "mu_sp",
                 (r"$a_1\phi/\mu_{sp}$", r"$(a_1\phi + a_2\phi^2)/\mu_{sp}$"), 6, rigid=True)

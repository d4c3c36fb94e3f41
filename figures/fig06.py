"""Figure 6: ratios of (a) a1 phi and (b) a1 phi + a2 phi^2 to mu_sp against phi for each
Ca, with the rigid-sphere (Krieger-Dougherty) ratios; 1 - (b) is the O(phi^3) share. Bars:
standard errors propagated from those of the time averages (the values and a1, a2).

Usage: python figures/fig06.py --out results/figures/fig06 results/grid/table.csv
       results/grid/fits.csv
"""

import numpy as np

import common
from analysis import fits
from analysis.statistics import propagated_standard_error


def share_errors(phi, values, errors, first, first_se, phi_max):
    """Standard errors of the first and second shares of fits.order_shares at every phi:
    the shares depend on c1, on the value at that phi and, through c2 (fitted over
    phi <= phi_max), on the values in the fitting range; all are independent averages.
    The O(phi^3) share has the second's error; without a phi in the fitting range (no
    c2) the errors are NaN."""
    n = len(phi)
    if not np.any((phi > 0) & (phi <= phi_max + 1e-12)):
        return np.full(n, np.nan), np.full(n, np.nan)

    def shares(v):
        c2 = fits.second_coefficient(phi, v[1:], v[0], phi_max)
        return np.concatenate(fits.order_shares(phi, v[1:], v[0], c2)[:2])

    se = propagated_standard_error(shares, np.concatenate([[first], values]),
                                   np.concatenate([[first_se], errors]))
    return se[:n], se[n:]


def share_figure(args, key, names, number, rigid):
    rows, dilute, susp, coef, coef_se, phi_max = common.coefficient_inputs(args, key)
    col = common.colors(coef)
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    for ca, (c1, c2) in sorted(coef.items()):
        phi, y = susp[ca]["phi"].to_numpy(), susp[ca][key].to_numpy()
        first, second, higher = fits.order_shares(phi, y, c1, c2)
        first_se, second_se = share_errors(phi, y, susp[ca][key + "_se"].to_numpy(), c1,
                                           coef_se[ca][0], phi_max)
        common.points(ax_a, phi, first, first_se, fmt="o-", color=col[ca],
                      label=f"Ca = {ca:g}")
        common.points(ax_b, phi, second, second_se, fmt="o-", color=col[ca],
                      label=f"Ca = {ca:g}")
        data += [{"ca": ca, "phi": p, "first_share": f, "first_share_se": fe,
                  "second_share": s, "second_share_se": se, "higher_share": h,
                  "higher_share_se": se}
                 for p, f, fe, s, h, se in zip(phi, first, first_se, second, higher,
                                               second_se)]
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
               f"1 - (b). The second coefficient fitted over 0 < phi <= {phi_max:g}. "
               "Bars: standard errors propagated from those of the time averages (the "
               "values and the coefficients; from the integrated autocorrelation time, "
               "docs/conventions.md); 1 - (b) has the error of (b). "
               + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    share_figure(common.parse_args(__doc__.splitlines()[0]), "mu_sp",
                 (r"$a_1\phi/\mu_{sp}$", r"$(a_1\phi + a_2\phi^2)/\mu_{sp}$"), 6, rigid=True)

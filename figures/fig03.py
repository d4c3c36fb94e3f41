"""Figure 3: (a) ensemble average of the Taylor parameter <D> and its slope d<D>/dphi,
(b) its standard deviation sigma_D, against phi (phi = 0: the dilute limit) for each Ca,
with standard errors (the slope's from the weighted fit, analysis.fits.linear_fit).

Usage: python figures/fig03.py --out results/figures/fig03 results/grid/table.csv
"""

import common
from analysis import fits


def panels(args, key, se_key, std_key, std_se_key, label, std_label, number):
    rows, dilute, susp = common.grid_rows(args.inputs[0])
    col = common.colors(susp)
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    for ca, runs in sorted(susp.items()):
        if ca not in dilute:
            continue
        phi, mean = common.phi_with_dilute(dilute[ca], runs, key)
        _, se = common.phi_with_dilute(dilute[ca], runs, se_key)
        _, std = common.phi_with_dilute(dilute[ca], runs, std_key)
        _, std_se = common.phi_with_dilute(dilute[ca], runs, std_se_key)
        intercept, slope, slope_se = fits.linear_fit(phi, mean, se)
        common.points(ax_a, phi, mean, se, color=col[ca],
                      label=f"Ca = {ca:g} (slope {slope:.3g} +- {slope_se:.2g})")
        ax_a.plot(phi, intercept + slope * phi, "--", color=col[ca], lw=0.8)
        common.points(ax_b, phi, std, std_se, fmt="o-", color=col[ca], label=f"Ca = {ca:g}")
        for p, m, e, s, s_e in zip(phi, mean, se, std, std_se):
            data.append({"panel": "a,b", "ca": ca, "phi": p, key: m, se_key: e, std_key: s,
                         std_se_key: s_e, "slope": slope, "slope_se": slope_se,
                         "intercept": intercept})
    ax_a.set(xlabel=r"$\phi$", ylabel=label, title="(a)")
    ax_b.set(xlabel=r"$\phi$", ylabel=std_label, title="(b)")
    ax_a.legend()
    ax_b.legend()
    caption = (f"Figure {number}. {label} with weighted least-squares lines (slope +- its "
               f"standard error in the legend) and {std_label} against phi; phi = 0 is the "
               "dilute limit. " + common.ERROR_BARS + "; in (b) that of the standard "
               "deviation, by the delta method. Slope error: the fit's, weighted by the "
               "points' errors, scaled by sqrt(reduced chi^2) where above 1. "
               + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    panels(common.parse_args(__doc__.splitlines()[0]), "D", "D_se", "D_std", "D_std_se",
           r"$\langle D\rangle$", r"$\sigma_D$", 3)

"""Figure 5: (a) specific viscosity mu_sp against phi for each Ca, with a1 phi + a2 phi^2
(grey dotted) and the Krieger-Dougherty curve of rigid spheres (eq. 4.7, black);
(b) the coefficients a1 (dilute limit) and a2 (least squares over 0 < phi <= phi_max, the
coefficient table's fitting range, 0.10 as the paper's) of
eq. 4.6 against Ca, with the rigid-sphere values of eq. 4.8. Bars: standard errors of the
time averages, and of a1, a2 propagated from them.

Usage: python figures/fig05.py --out results/figures/fig05 results/grid/table.csv
       results/grid/fits.csv
"""

import numpy as np

import common
from analysis import fits


def polynomial_figure(args, key, c_names, ylabel, number, rigid):
    rows, dilute, susp, coef, coef_se, phi_max = common.coefficient_inputs(args, key)
    col = common.colors(coef)
    fig, (ax_a, ax_b) = common.plt.subplots(1, 2, figsize=(7.0, 3.0))
    data = []
    smooth = np.linspace(0, max(runs["phi"].max() for runs in susp.values()), 60)
    for ca, (c1, c2) in sorted(coef.items()):
        phi, y = common.phi_with_dilute(dilute[ca], susp[ca], key, dilute_value=0.0)
        _, se = common.phi_with_dilute(dilute[ca], susp[ca], key + "_se", dilute_value=0.0)
        common.points(ax_a, phi, y, se, color=col[ca], label=f"Ca = {ca:g}")
        ax_a.plot(smooth, c1 * smooth + c2 * smooth**2, ":", color="0.5")
        data += [{"panel": "a", "ca": ca, "phi": p, key: v, key + "_se": e}
                 for p, v, e in zip(phi, y, se)]
        data.append({"panel": "b", "ca": ca, c_names[0]: c1,
                     c_names[0] + "_se": coef_se[ca][0], c_names[1]: c2,
                     c_names[1] + "_se": coef_se[ca][1]})
    if rigid:
        ax_a.plot(smooth, fits.kd_specific_viscosity(smooth, args.phi_m), "k-",
                  label=f"rigid spheres (KD, phi_m = {args.phi_m:g})")
        kd = fits.kd_coefficients(2, args.phi_m)
        ax_b.axhline(kd[0], color="k", ls="-", lw=0.8, label=f"rigid a1 = {kd[0]:.3g}")
        ax_b.axhline(kd[1], color="k", ls="--", lw=0.8, label=f"rigid a2 = {kd[1]:.3g}")
        data.append({"panel": "b", "ca": 0.0, "series": "krieger-dougherty",
                     c_names[0]: kd[0], c_names[1]: kd[1], "phi_m": args.phi_m})
    cas = sorted(coef)
    for i, (fmt, color) in enumerate((("o-", "C0"), ("s--", "C3"))):
        common.points(ax_b, cas, [coef[c][i] for c in cas], [coef_se[c][i] for c in cas],
                      fmt=fmt, color=color, label=c_names[i])
    ax_a.set(xlabel=r"$\phi$", ylabel=ylabel, title="(a)")
    ax_b.set(xlabel="Ca", ylabel=f"{c_names[0]}, {c_names[1]}", title="(b)")
    ax_a.legend()
    ax_b.legend()
    caption = (f"Figure {number}. (a) {ylabel} against phi; grey dotted: "
               f"{c_names[0]} phi + {c_names[1]} phi^2. (b) {c_names[0]} from the dilute limit, "
               f"{c_names[1]} by least squares of (y - {c_names[0]} phi) = {c_names[1]} phi^2 "
               f"over 0 < phi <= {phi_max:g}. "
               + common.ERROR_BARS + f"; those of {c_names[0]}, {c_names[1]} propagated "
               "from them. " + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    polynomial_figure(common.parse_args(__doc__.splitlines()[0]), "mu_sp", ("a1", "a2"),
                      r"$\mu_{sp}$", 5, rigid=True)

"""Figure 7: normal stress differences: (a) N1 and (b) N2 (over mu gammadot) against Ca for
each phi; (c) N1 against phi for each Ca with b1 phi + b2 phi^2; (d) the coefficients b1
(dilute limit) and b2 (least squares over 0 < phi <= phi_max) of eq. 4.11 against Ca. Bars:
standard errors of the time averages, and of b1, b2 propagated from them.

Usage: python figures/fig07.py --out results/figures/fig07 results/grid/table.csv
       results/grid/fits.csv
"""

import numpy as np

import common


def main(args):
    rows, dilute, susp, coef, coef_se, phi_max = common.coefficient_inputs(args, "N1")
    fig, axes = common.plt.subplots(2, 2, figsize=(7.0, 5.6))
    (ax_a, ax_b), (ax_c, ax_d) = axes
    data = []
    # Every suspension row, also those of runs stopped before their window (NaN: no point).
    susp_rows = rows[rows["intrinsic"] == 0].sort_values("ca", kind="stable")
    col_phi = common.colors(susp_rows["phi"].unique())
    for phi, runs in susp_rows.groupby("phi"):
        for ax, key in ((ax_a, "N1"), (ax_b, "N2")):
            common.points(ax, runs["ca"], runs[key], runs[key + "_se"], fmt="o-",
                          color=col_phi[phi], label=f"phi = {phi:g}")
        data += [{"panel": "a,b", "ca": r.ca, "phi": phi, "N1": r.N1, "N1_se": r.N1_se,
                  "N2": r.N2, "N2_se": r.N2_se} for r in runs.itertuples()]
    col = common.colors(coef)
    smooth = np.linspace(0, susp_rows["phi"].max(), 60)
    for ca, (b1, b2) in sorted(coef.items()):
        phi, n1 = common.phi_with_dilute(dilute[ca], susp[ca], "N1", dilute_value=0.0)
        _, se = common.phi_with_dilute(dilute[ca], susp[ca], "N1_se", dilute_value=0.0)
        common.points(ax_c, phi, n1, se, color=col[ca], label=f"Ca = {ca:g}")
        ax_c.plot(smooth, b1 * smooth + b2 * smooth**2, ":", color="0.5")
        data.append({"panel": "d", "ca": ca, "b1": b1, "b1_se": coef_se[ca][0], "b2": b2,
                     "b2_se": coef_se[ca][1]})
    cas = sorted(coef)
    for i, (fmt, name) in enumerate((("o-", "b1"), ("s--", "b2"))):
        common.points(ax_d, cas, [coef[c][i] for c in cas], [coef_se[c][i] for c in cas],
                      fmt=fmt, label=name)
    ax_a.set(xlabel="Ca", ylabel=r"$N_1/\mu\dot\gamma$", title="(a)")
    ax_b.set(xlabel="Ca", ylabel=r"$N_2/\mu\dot\gamma$", title="(b)")
    ax_c.set(xlabel=r"$\phi$", ylabel=r"$N_1/\mu\dot\gamma$", title="(c)")
    ax_d.set(xlabel="Ca", ylabel="b1, b2", title="(d)")
    for ax in axes.flat:
        ax.legend()
    fig.tight_layout()
    caption = ("Figure 7. Normal stress differences; grey dotted in (c): b1 phi + b2 phi^2, "
               f"b2 fitted over 0 < phi <= {phi_max:g}. " + common.ERROR_BARS
               + "; those of b1, b2 propagated from them. "
               + common.footer(rows, args.t_start))
    common.save(fig, args.out, data, caption)


if __name__ == "__main__":
    main(common.parse_args(__doc__.splitlines()[0]))

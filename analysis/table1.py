"""Table 1: effect of the number of elements N_E on <D> and mu_sp, with the errors of
eqs. A1 and A2 against the reference, the mean of the cases at the finest mesh. Every
average carries its standard error ("0.3744 +- 0.0026"); the reference that of the mean
of the cases, every eps that propagated from the value's and the reference's, and the CSV
also the standard deviation of the cases (appendix A.2) and each run's averaging window
(t_start, t_end), which the caption states per mesh.

Usage: python -m analysis.table1 --out results/figures/table1 results/mesh/table.csv
       (or figures/table1.py, the workflow's entry)
Writes STEM.md and STEM.csv.
"""

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.averages import ensemble
from analysis.statistics import mean_of_runs_standard_error, propagated_standard_error
from analysis.tables import markdown_table, read_table, with_data, write_table


def eps_standard_errors(values, errors, finest):
    """Standard errors of eps_i = |x_i - ref| / ref (eqs. A1, A2) of each run i, ref the
    mean of the runs marked in `finest`, from the runs' standard errors (independent
    averages), to first order: those of x_i / ref, since eps = |x_i / ref - 1|. The ratio
    rather than the |.| itself: central differences across the kink of |.| would shrink
    the error of an eps smaller than its error. A finest-mesh case enters both x_i and ref,
    and counts once (every run is one entry of the propagation)."""
    values = np.asarray(values, dtype=float)
    return [propagated_standard_error(lambda v, i=i: v[i] / v[finest].mean(), values, errors)
            for i in range(values.size)]


def table_rows(runs):
    """Rows of Table 1: one per coarse level, one per case at the finest, and the reference
    (a DataFrame)."""
    finest = runs["mesh_level"].max()
    fine = runs[runs["mesh_level"] == finest]
    ref_d, ref_mu = fine["D"].mean(), fine["mu_sp"].mean()
    runs = runs.sort_values(["mesh_level", "seed"], kind="stable")
    n_e = 20 * 4 ** runs["mesh_level"].astype(int)
    cases = (runs["mesh_level"] == finest) & (len(fine) > 1)
    labels = n_e.astype(str) + runs["seed"].map(lambda s: f" (case {int(s)})").where(cases, "")
    at_finest = (runs["mesh_level"] == finest).to_numpy()
    rows = pd.DataFrame({"N_E": n_e, "label": labels, "seed": runs["seed"].astype(int),
                         "t_start": runs["t_start"], "t_end": runs["t_end"],
                         "ended": runs["ended"] if "ended" in runs else "t_end",
                         "D": runs["D"], "D_se": runs["D_se"],
                         "eps_D": (runs["D"] - ref_d).abs() / ref_d,  # eq. A1
                         "eps_D_se": eps_standard_errors(runs["D"], runs["D_se"], at_finest),
                         "mu_sp": runs["mu_sp"], "mu_sp_se": runs["mu_sp_se"],
                         "eps_mu": (runs["mu_sp"] - ref_mu).abs() / ref_mu,  # eq. A2
                         "eps_mu_se": eps_standard_errors(runs["mu_sp"], runs["mu_sp_se"],
                                                          at_finest)})
    n_e = 20 * 4 ** int(finest)
    # The reference: the mean of the independent cases, its standard error
    # sqrt(sum se_i^2) / n, and the standard deviation of the cases (population form).
    reference = {"N_E": n_e, "label": f"{n_e} (average): reference", "seed": "mean",
                 "D": ref_d, "D_se": mean_of_runs_standard_error(fine["D_se"]),
                 "D_std": ensemble(fine["D"])[1], "mu_sp": ref_mu,
                 "mu_sp_se": mean_of_runs_standard_error(fine["mu_sp_se"]),
                 "mu_sp_std": ensemble(fine["mu_sp"])[1]}
    return pd.concat([rows, pd.DataFrame([reference])], ignore_index=True)


def windows(rows):
    """The averaging windows of the runs, per mesh: "N_E 320 [10, 14.7] (contact), ..."."""
    parts = []
    for r in rows[rows["seed"].astype(str) != "mean"].itertuples():
        ended = "" if str(r.ended) in ("t_end", "nan") else f" ({r.ended})"
        parts.append(f"{r.label} [{r.t_start:g}, {r.t_end:.3g}]{ended}")
    return ", ".join(parts)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("table")
    args, _ = ap.parse_known_args(argv)
    runs = with_data(read_table(args.table))
    runs = runs[runs["intrinsic"] == 0]
    rows = table_rows(runs)
    r0 = runs.iloc[0]
    out = Path(args.out)
    write_table(out.with_suffix(".csv"), rows)
    columns = ["label", "D", "eps_D", "mu_sp", "eps_mu"]
    lines = [markdown_table(rows[columns], {"D": ".5f", "eps_D": ".4f", "mu_sp": ".5f",
                                            "eps_mu": ".4f"},
                            headers=["N_E", "<D>", "eps_D", "mu_sp", "eps_mu"], na_rep="-",
                            errors={"D": rows["D_se"], "eps_D": rows["eps_D_se"],
                                    "mu_sp": rows["mu_sp_se"], "eps_mu": rows["eps_mu_se"]})]
    ref = rows.iloc[-1]
    lines += ["", f"Table 1. Ca = {r0['ca']:g}, phi = {r0['phi']:g}, M = {int(r0['capsules'])}, "
              f"averages over gammadot t in {windows(rows)}; errors "
              "(eqs. A1, A2) against the mean of the finest-mesh cases. +-: the standard "
              "error of the time average, from the integrated autocorrelation time "
              "(docs/conventions.md); for the reference that of the mean of the cases, "
              "sqrt(sum se_i^2) / n; for eps propagated to first order from those of "
              "the value and the reference. Standard deviation of the cases (appendix A.2): "
              f"<D> {ref['D_std']:.2g}, mu_sp {ref['mu_sp_std']:.2g}."]
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

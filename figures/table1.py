"""Table 1: effect of the number of elements N_E on <D> and mu_sp, with the errors of
eqs. A1 and A2 against the reference, the mean of the cases at the finest mesh.

Usage: python figures/table1.py --out results/figures/table1 results/mesh/table.csv
Writes STEM.md and STEM.csv.
"""

import argparse
from pathlib import Path

import pandas as pd

from analysis.tables import markdown_table, read_table, with_data, write_table


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
    rows = pd.DataFrame({"N_E": n_e, "label": labels, "seed": runs["seed"].astype(int),
                         "D": runs["D"], "eps_D": (runs["D"] - ref_d).abs() / ref_d,  # eq. A1
                         "mu_sp": runs["mu_sp"],
                         "eps_mu": (runs["mu_sp"] - ref_mu).abs() / ref_mu})  # eq. A2
    n_e = 20 * 4 ** int(finest)
    reference = {"N_E": n_e, "label": f"{n_e} (average): reference", "seed": "mean",
                 "D": ref_d, "mu_sp": ref_mu}
    return pd.concat([rows, pd.DataFrame([reference])], ignore_index=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("table")
    args, _ = ap.parse_known_args()
    runs = with_data(read_table(args.table))
    runs = runs[runs["intrinsic"] == 0]
    rows = table_rows(runs)
    r0 = runs.iloc[0]
    out = Path(args.out)
    write_table(out.with_suffix(".csv"), rows)
    columns = ["label", "D", "eps_D", "mu_sp", "eps_mu"]
    lines = [markdown_table(rows[columns], {"D": ".5f", "eps_D": ".4f", "mu_sp": ".5f",
                                            "eps_mu": ".4f"},
                            headers=["N_E", "<D>", "eps_D", "mu_sp", "eps_mu"], na_rep="-")]
    lines += ["", f"Table 1. Ca = {r0['ca']:g}, phi = {r0['phi']:g}, M = {int(r0['capsules'])}, "
              f"averages over gammadot t in [{r0['t_start']:g}, {r0['t_end']:.3g}]; errors "
              "(eqs. A1, A2) against the mean of the finest-mesh cases."]
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

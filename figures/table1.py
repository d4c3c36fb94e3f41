"""Table 1: effect of the number of elements N_E on <D> and mu_sp, with the errors of
eqs. A1 and A2 against the reference, the mean of the cases at the finest mesh.

Usage: python figures/table1.py --out results/figures/table1 results/mesh/table.csv
Writes STEM.md and STEM.csv.
"""

import argparse
from pathlib import Path

from analysis.tables import read_table, with_data, write_table


def table_rows(runs):
    """Rows of Table 1: one per coarse level, one per case at the finest, and the reference."""
    finest = max(int(r["mesh_level"]) for r in runs)
    fine = sorted((r for r in runs if int(r["mesh_level"]) == finest), key=lambda r: r["seed"])
    ref_d = sum(r["D"] for r in fine) / len(fine)
    ref_mu = sum(r["mu_sp"] for r in fine) / len(fine)
    rows = []
    for r in sorted(runs, key=lambda r: (r["mesh_level"], r["seed"])):
        n_e = 20 * 4 ** int(r["mesh_level"])
        case = f" (case {int(r['seed'])})" if int(r["mesh_level"]) == finest and len(fine) > 1 else ""
        rows.append({"N_E": n_e, "label": f"{n_e}{case}", "seed": int(r["seed"]),
                     "D": r["D"], "eps_D": abs(r["D"] - ref_d) / ref_d,  # eq. A1
                     "mu_sp": r["mu_sp"], "eps_mu": abs(r["mu_sp"] - ref_mu) / ref_mu})  # A2
    n_e = 20 * 4 ** finest
    rows.append({"N_E": n_e, "label": f"{n_e} (average): reference", "seed": "mean",
                 "D": ref_d, "eps_D": "", "mu_sp": ref_mu, "eps_mu": ""})
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("table")
    args, _ = ap.parse_known_args()
    runs = [r for r in with_data(read_table(args.table)) if not r["intrinsic"]]
    rows = table_rows(runs)
    r0 = runs[0]
    out = Path(args.out)
    write_table(out.with_suffix(".csv"), rows)
    lines = ["| N_E | <D> | eps_D | mu_sp | eps_mu |", "|---|---|---|---|---|"]
    for r in rows:
        eps = [f"{r[k]:.4f}" if r[k] != "" else "-" for k in ("eps_D", "eps_mu")]
        lines.append(f"| {r['label']} | {r['D']:.5f} | {eps[0]} | {r['mu_sp']:.5f} | {eps[1]} |")
    lines += ["", f"Table 1. Ca = {r0['ca']:g}, phi = {r0['phi']:g}, M = {int(r0['capsules'])}, "
              f"averages over gammadot t in [{r0['t_start']:g}, {r0['t_end']:.3g}]; errors "
              "(eqs. A1, A2) against the mean of the finest-mesh cases."]
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

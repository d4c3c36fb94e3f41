"""Dilute-limit table: steady D, theta_D, [mu], [N1], [N2] for every Ca and mesh level,
with the observed mesh-convergence order and the small-deformation limits.

Usage: python figures/dilute_table.py --out-md T.md --out-csv T.csv RUN/summary.json ...
"""

import argparse
import csv
from pathlib import Path

from analysis.fits import observed_order
from analysis.read_run import read_summary

QUANTITIES = [
    ("taylor_D", "D"),
    ("theta_D_deg", "theta_D (deg)"),
    ("mu_sp", "[mu]"),
    ("N1", "[N1]"),
    ("N2", "[N2]"),
]


def collect(paths):
    runs = {}
    for path in paths:
        s = read_summary(Path(path).parent)
        p = s["parameters"]
        runs[(float(p["ca"]), int(p["mesh_level"]))] = s
    return runs


def table_rows(runs):
    cas = sorted({ca for ca, _ in runs})
    levels = sorted({lv for _, lv in runs})
    rows = []
    for ca in cas:
        for key, label in QUANTITIES:
            values = [runs[(ca, lv)][key] if (ca, lv) in runs else float("nan") for lv in levels]
            order = observed_order(*values[-3:]) if len(levels) >= 3 else float("nan")
            rows.append({"ca": ca, "quantity": label, "levels": levels, "values": values,
                         "order": order})
    return levels, rows


def small_deformation_lines(runs, levels):
    """Small-Ca checks: D -> (25/12) Ca for a neo-Hookean capsule with lambda = 1
    (Barthes-Biesel & Rallison 1981), and [mu] -> 5/2 (Einstein)."""
    ca = min(ca for ca, _ in runs)
    fine = max(levels)
    s = runs[(ca, fine)]
    d_theory = 25.0 / 12.0 * ca
    return [
        f"Smallest Ca = {ca} at level {fine}: D = {s['taylor_D']:.5f} vs (25/12) Ca = "
        f"{d_theory:.5f} ({100 * (s['taylor_D'] / d_theory - 1):+.2f} %); "
        f"[mu] = {s['mu_sp']:.4f} vs 2.5 ({100 * (s['mu_sp'] / 2.5 - 1):+.2f} %).",
    ]


def write_markdown(path, levels, rows, notes):
    head = "| Ca | quantity | " + " | ".join(f"level {lv}" for lv in levels) + " | order |"
    lines = [head, "|" + "---|" * (len(levels) + 3)]
    for r in rows:
        vals = " | ".join(f"{v:.5g}" for v in r["values"])
        lines.append(f"| {r['ca']} | {r['quantity']} | {vals} | {r['order']:.2f} |")
    Path(path).write_text("\n".join(lines + [""] + notes) + "\n")


def write_csv(path, levels, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["ca", "quantity"] + [f"level_{lv}" for lv in levels] + ["order"])
        for r in rows:
            w.writerow([r["ca"], r["quantity"]] + r["values"] + [r["order"]])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out-md", required=True)
    ap.add_argument("--out-csv", required=True)
    ap.add_argument("summaries", nargs="+")
    args = ap.parse_args()
    runs = collect(args.summaries)
    levels, rows = table_rows(runs)
    notes = small_deformation_lines(runs, levels)
    write_markdown(args.out_md, levels, rows, notes)
    write_csv(args.out_csv, levels, rows)
    print("\n".join(notes))


if __name__ == "__main__":
    main()

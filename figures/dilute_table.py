"""Dilute-limit table: steady D, theta_D, [mu], [N1], [N2] for every Ca and mesh level,
with the observed mesh-convergence order and the small-deformation limits. Every value
carries the standard error of its time average (markdown "2.036 +- 1.2e-05"; CSV columns
level_<l>_se), from the run's time series (timeseries.h5 beside summary.json).

Usage: python figures/dilute_table.py --out-md T.md --out-csv T.csv RUN/summary.json ...
"""

import argparse
from pathlib import Path

import pandas as pd

from analysis.averages import run_averages
from analysis.fits import observed_order
from analysis.read_run import read_summary, read_timeseries
from analysis.tables import markdown_table, rheology_standard_errors, write_table

QUANTITIES = [
    ("taylor_D", "D"),
    ("theta_D_deg", "theta_D (deg)"),
    ("mu_sp", "[mu]"),
    ("N1", "[N1]"),
    ("N2", "[N2]"),
]
# The standard error of each summary value, under its name in analysis.averages/tables.
STANDARD_ERRORS = {"taylor_D": "D_se", "theta_D_deg": "theta_D_se_deg", "mu_sp": "mu_sp_se",
                   "N1": "N1_se", "N2": "N2_se"}


def standard_errors(run_dir, summary):
    """The standard errors of the summary's averages (window [t_avg_start, last sample]),
    keyed as QUANTITIES; the rheology's are those of the intrinsic values (phi = 0)."""
    avg = run_averages(read_timeseries(run_dir), float(summary["t_avg_start"]))
    avg.update(rheology_standard_errors(avg, 0.0, float(summary["parameters"]["ca"])))
    return {f"{key}_se": float(avg[name]) for key, name in STANDARD_ERRORS.items()}


def collect(paths):
    """One row per run: ca, mesh_level, the summary values of QUANTITIES and their
    standard errors (<key>_se)."""
    runs = []
    for path in paths:
        s = read_summary(Path(path).parent)
        p = s["parameters"]
        runs.append({"ca": float(p["ca"]), "mesh_level": int(p["mesh_level"]),
                     **{key: s[key] for key, _ in QUANTITIES},
                     **standard_errors(Path(path).parent, s)})
    return pd.DataFrame(runs)


def table_rows(runs):
    """The levels and the table: one row per Ca and quantity (in QUANTITIES order), a
    column level_<l> per mesh level (NaN where that run is missing), the observed order
    from the three finest levels, and the standard errors level_<l>_se."""
    labels = [label for _, label in QUANTITIES]

    def wide_by_level(columns):
        long = runs.rename(columns=dict(zip(columns, labels))).melt(
            id_vars=["ca", "mesh_level"], value_vars=labels, var_name="quantity")
        long["quantity"] = pd.Categorical(long["quantity"], categories=labels, ordered=True)
        return long.pivot(index=["ca", "quantity"], columns="mesh_level", values="value")

    wide = wide_by_level([key for key, _ in QUANTITIES])
    errors = wide_by_level([f"{key}_se" for key, _ in QUANTITIES])
    levels = list(wide.columns)
    order = (wide.apply(lambda values: observed_order(*values.iloc[-3:]), axis=1)
             if len(levels) >= 3 else float("nan"))
    table = wide.rename(columns=lambda lv: f"level_{lv}").assign(order=order)
    table = table.join(errors.rename(columns=lambda lv: f"level_{lv}_se"))
    table = table.reset_index().rename_axis(columns=None)
    table["quantity"] = table["quantity"].astype(str)
    return levels, table


def small_deformation_lines(runs, levels):
    """Small-Ca checks: D -> (25/12) Ca for a neo-Hookean capsule with lambda = 1
    (Barthes-Biesel & Rallison 1981), and [mu] -> 5/2 (Einstein)."""
    ca = runs["ca"].min()
    fine = max(levels)
    s = runs[(runs["ca"] == ca) & (runs["mesh_level"] == fine)].iloc[-1]
    d_theory = 25.0 / 12.0 * ca
    return [
        f"Smallest Ca = {ca} at level {fine}: D = {s['taylor_D']:.5f} vs (25/12) Ca = "
        f"{d_theory:.5f} ({100 * (s['taylor_D'] / d_theory - 1):+.2f} %); "
        f"[mu] = {s['mu_sp']:.4f} vs 2.5 ({100 * (s['mu_sp'] / 2.5 - 1):+.2f} %).",
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out-md", required=True)
    ap.add_argument("--out-csv", required=True)
    ap.add_argument("summaries", nargs="+")
    args = ap.parse_args()
    runs = collect(args.summaries)
    levels, table = table_rows(runs)
    notes = small_deformation_lines(runs, levels)
    formats = {f"level_{lv}": ".5g" for lv in levels} | {"order": ".2f"}
    headers = ["Ca", "quantity"] + [f"level {lv}" for lv in levels] + ["order"]
    shown = ["ca", "quantity"] + [f"level_{lv}" for lv in levels] + ["order"]
    markdown = markdown_table(table[shown], formats, headers,
                              errors={f"level_{lv}": table[f"level_{lv}_se"] for lv in levels})
    notes.append("+-: the standard error of the time average, from the integrated "
                 "autocorrelation time (docs/conventions.md).")
    Path(args.out_md).write_text("\n".join([markdown, ""] + notes) + "\n")
    write_table(args.out_csv, table)
    print("\n".join(notes))


if __name__ == "__main__":
    main()

"""The viscosity-ratio study: one capsule in unbounded shear whose interior is lambda
times as viscous as the suspending fluid (capsim's `lambda`), at every Ca and lambda of
config viscosity_ratio. The paper has lambda = 1 only; the other ratios go beyond it.

One row per (Ca, lambda): <D>, theta_D, the intrinsic viscosity [mu] = mu_sp / phi as
phi -> 0 and [N1], [N2] (analysis.tables.run_row, the dilute study's reduction), each with
the standard error of its time average over [t_start, last sample]; how the run ended
(`t_end`, or capsim's `numerical` for a membrane that folded or a step that failed, at
`t_stop`), the GMRES iterations per solve of its last invocation (summary.json; none
at lambda 1, where nothing is solved), and the tank-treading frequency over gammadot from
the run's last snapshot (analysis.tank_treading; one instant of the steady state, so no
standard error; NaN where that snapshot is before t_start or the membrane does not
tank-tread there).

The dense part (viscosity_ratio.dense, --dense): the grid's suspension at the Table 1
point's Ca (M capsules in the sheared periodic box) at other ratios, one row per (phi,
lambda) with <D>, theta_D, mu_sp, N1, N2 and their standard errors, how each run ended,
the end it was planned to (`t_planned`) and its GMRES counts; lambda 1 rows are the
grid's own runs.

    python -m analysis.viscosity_ratio [--dense] --runs JSON --t-start 10 --out-csv T.csv \
        --out-md T.md

JSON: a list of {"ca", "lambda", "folder"} (and "phi" for --dense), one per run
(workflow/rules/viscosity_ratio.smk).
"""

import argparse
import json
import math
import sys
from pathlib import Path

import pandas as pd

from analysis import tank_treading
from analysis.read_run import read_summary
from analysis.tables import markdown_table, run_row, stopped_row, write_table

QUANTITIES = ("D", "theta_D_deg", "mu_sp", "N1", "N2")
SE = {"theta_D_deg": "theta_D_se_deg"}  # the standard error's column where not <q>_se
GMRES = ("gmres_solves", "gmres_iterations_mean", "gmres_iterations_max")
COLUMNS = (("ca", "lambda", "mesh_level", "N_E", "ended", "t_stop", "t_start", "t_end",
            "count")
           + tuple(c for q in QUANTITIES for c in (q, SE.get(q, f"{q}_se")))
           + GMRES + ("tank_treading",)
           # for figures/common.footer(): one capsule, phi 0, the paper's membrane
           + ("phi", "capsules", "seed", "intrinsic", "membrane", "run"))
# A dense row also carries the end its run was planned to (summary.json's t_end): the
# figure draws a run that stopped early where its window holds enough of the planned one.
DENSE_COLUMNS = tuple(c for c in COLUMNS if c != "tank_treading") + ("t_planned",)


def run_ratio(summary):
    """The viscosity ratio a run carried (summary.json's parameters; a run recorded
    before capsim had the key carried 1)."""
    return float(summary.get("parameters", {}).get("lambda", 1.0))


def averages(entry, t_start):
    """The averages of one run from t_start (run_row) or, where it stopped before
    t_start, its stopped_row (count 0, NaN averages), how it ended and when, and its
    GMRES counts. Refuses a folder whose run carried another lambda (made by other
    options: delete it to run it again)."""
    path = Path(entry["folder"])
    summary = read_summary(path)
    if not math.isclose(run_ratio(summary), float(entry["lambda"]), rel_tol=1e-12):
        raise ValueError(f"viscosity_ratio: {path} carries lambda {run_ratio(summary):g}, "
                         f"not {float(entry['lambda']):g}: delete the folder to run it again")
    try:
        row = run_row(path, t_start)
    except ValueError:  # no samples from t_start on: a run that stopped before them
        if summary.get("ended", "t_end") == "t_end":
            raise
        row = stopped_row(path, t_start)
    level = int(row["mesh_level"])
    out = {"ca": float(entry["ca"]), "lambda": float(entry["lambda"]), "mesh_level": level,
           "N_E": 20 * 4**level, "ended": summary.get("ended", "t_end"),
           # t_end of a row is its last sample: where a stopped run stopped
           "t_stop": row["t_end"], "t_start": row["t_start"], "t_end": row["t_end"],
           "count": int(row["count"]),
           "t_planned": float(summary["parameters"]["t_end"])}
    for q in QUANTITIES:
        se = SE.get(q, f"{q}_se")
        out[q], out[se] = float(row[q]), float(row[se])
    # summary.json writes a value that is not finite as null, and none at lambda 1
    out.update({key: float(summary.get(key) if summary.get(key) is not None else math.nan)
                for key in GMRES})
    out.update({"phi": float(row["phi"]), "capsules": int(row["capsules"]),
                "seed": int(row["seed"]), "intrinsic": int(row["intrinsic"]),
                "membrane": row["membrane"], "run": str(path)})
    return out


def run_values(entry, t_start):
    """One row of the dilute table: averages() and the tank-treading frequency."""
    return averages(entry, t_start) | {
        "tank_treading": tank_treading.run_frequency(entry["folder"], t_start)}


def study_table(runs, t_start):
    """The table (a DataFrame, COLUMNS): one row per run, by Ca then lambda."""
    table = pd.DataFrame([run_values(entry, t_start) for entry in runs],
                         columns=list(COLUMNS))
    return table.sort_values(["ca", "lambda"], kind="stable").reset_index(drop=True)


def dense_table(runs, t_start):
    """The dense table (a DataFrame, DENSE_COLUMNS): one row per run, by phi then
    lambda."""
    table = pd.DataFrame([averages(entry, t_start) for entry in runs],
                         columns=list(DENSE_COLUMNS))
    return table.sort_values(["phi", "lambda"], kind="stable").reset_index(drop=True)


def ended_text(row):
    if row["ended"] == "t_end":
        return "t_end"
    return f"{row['ended']} at {row['t_stop']:.3g}"


def gmres_text(row):
    if pd.isna(row["gmres_iterations_mean"]):
        return "none (lambda 1)" if row["lambda"] == 1 else "not reported"
    return f"{row['gmres_iterations_mean']:.1f} (max {int(row['gmres_iterations_max'])})"


def markdown(table):
    """The table as markdown: each average +- its standard error, how each run ended
    and its GMRES iterations per solve, then a line on the window and what is missing."""
    shown = pd.DataFrame({"ca": table["ca"], "lambda": table["lambda"],
                          **{q: table[q] for q in QUANTITIES},
                          "tank_treading": table["tank_treading"],
                          "gmres": table.apply(gmres_text, axis=1),
                          "ended": table.apply(ended_text, axis=1)})
    errors = {q: table[SE.get(q, f"{q}_se")] for q in QUANTITIES}
    formats = {"ca": "g", "lambda": "g", "tank_treading": ".4g"} | {
        q: ".4g" for q in QUANTITIES}
    headers = ["Ca", "lambda", "<D>", "theta_D (deg)", "[mu]", "[N1]", "[N2]",
               "tank-treading frequency / gammadot", "GMRES iterations per solve", "ended"]
    levels = ", ".join(str(n) for n in sorted(set(table["N_E"])))
    starts = ", ".join(f"{t:g}" for t in sorted(set(table["t_start"].dropna())))
    notes = [f"One capsule in unbounded shear, N_E {levels}, averages from gammadot t = "
             f"{starts} to each run's last sample; +-: the standard error of the time "
             "average (docs/conventions.md). [mu], [N1], [N2]: intrinsic values (mu_sp, "
             "N1, N2 over phi as phi -> 0). The paper has lambda = 1 only: the other rows "
             "are beyond it. GMRES: the mean (and largest) iterations per second-kind "
             "solve of the run's last invocation. Tank-treading frequency: 2 pi over the "
             "period of a membrane point's orbit near the shear plane, from the last "
             "snapshot's node velocities (analysis/tank_treading.py; a rigid sphere's is "
             "1/2); nan where the run has no snapshot in the averaging window or the "
             "membrane does not turn all the way round."]
    return "\n".join([markdown_table(shown, formats, headers, errors=errors), ""] + notes)


def dense_markdown(table):
    """The dense table as markdown: each average +- its standard error, how each run
    ended and its GMRES iterations per solve, then a line on the runs."""
    shown = pd.DataFrame({"phi": table["phi"], "lambda": table["lambda"],
                          **{q: table[q] for q in QUANTITIES},
                          "gmres": table.apply(gmres_text, axis=1),
                          "ended": table.apply(ended_text, axis=1)})
    errors = {q: table[SE.get(q, f"{q}_se")] for q in QUANTITIES}
    formats = {"phi": "g", "lambda": "g"} | {q: ".4g" for q in QUANTITIES}
    headers = ["phi", "lambda", "<D>", "theta_D (deg)", "mu_sp", "N1", "N2",
               "GMRES iterations per solve", "ended"]
    cases = ", ".join(sorted({f"Ca {r['ca']:g}, M {r['capsules']}, N_E {r['N_E']}"
                              for r in table.to_dict("records")}))
    starts = ", ".join(f"{t:g}" for t in sorted(set(table["t_start"].dropna())))
    notes = [f"The suspension in the sheared periodic box ({cases}), averages from "
             f"gammadot t = {starts} to each run's last sample; +-: the standard error of "
             "the time average (docs/conventions.md). lambda 1: the grid's own runs (the "
             "paper's suspension); the other rows are beyond the paper."]
    return "\n".join([markdown_table(shown, formats, headers, errors=errors), ""] + notes)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dense", action="store_true",
                    help="the suspensions' table (viscosity_ratio.dense)")
    ap.add_argument("--runs", required=True, help="the runs as JSON (module docstring)")
    ap.add_argument("--t-start", type=float, required=True,
                    help="start of the averages (config viscosity_ratio t_avg_start)")
    ap.add_argument("--out-csv", required=True)
    ap.add_argument("--out-md", required=True)
    args = ap.parse_args(argv)
    runs = json.loads(args.runs)
    table = dense_table(runs, args.t_start) if args.dense else study_table(runs, args.t_start)
    write_table(args.out_csv, table)
    text = dense_markdown(table) if args.dense else markdown(table)
    Path(args.out_md).write_text(text + "\n", encoding="utf-8")
    stopped = table[table["ended"] != "t_end"]
    for row in stopped.to_dict("records"):
        print(f"viscosity_ratio: Ca {row['ca']:g}, phi {row['phi']:g}, lambda "
              f"{row['lambda']:g} stopped early: {ended_text(row)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The paper's membrane where it folds, as the limit eb -> 0 of bending membranes.

Where the paper's membrane (neo-Hookean, no bending) folds before the averaging window
ends, the grid runs a bending modulus eb (`grid.membranes`, docs/suspensions.md). Bending
stiffens the capsule about in proportion to eb while eb is small: one capsule at Ca 0.6,
level 3 has D = 0.520, 0.509, 0.497, 0.476 at eb = 0, 0.0056, 0.0125, 0.025, within 0.002
of a line (docs/suspensions.md, "Hard cases"). So each such point is run again at the
smaller moduli of `eblimit.eb` (its other tokens, the repulsion, kept), and each average
is extrapolated to eb = 0 along the least-squares line through the point's moduli,
weighted by their standard errors (with two moduli, the line through both).

The extrapolation's own error is measured where the answer is known: one capsule in
unbounded shear at the same Ca and mesh, run at the same moduli, extrapolated the same
way and compared with the dilute study's run without bending. Its relative miss, applied
to the suspension's extrapolated value, is added to the statistical standard error in
quadrature (`<q>_model`, included in `<q>_se`).

    python -m analysis.bending_limit --grid JSON --runs JSON --t-start 10
        --dilute-t-start 10 --out-csv T.csv --out-md T.md
"""

import argparse
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from analysis import membrane
from analysis.statistics import propagated_standard_error
from analysis.tables import markdown_table, run_row, write_table

QUANTITIES = ("D", "theta_D_deg", "mu_sp", "N1", "N2")
SE = {"theta_D_deg": "theta_D_se_deg"}  # the standard error's column where not <q>_se


@dataclass(frozen=True)
class Point:
    """A grid point that carries bending: its Ca, phi and the grid's membrane code."""
    ca: float
    phi: float
    code: str

    @property
    def eb(self):
        return membrane.parse(self.code, "grid.membranes")["eb"]

    def at(self, eb):
        """The point's code with the bending modulus eb, its other tokens kept."""
        return membrane.spell(membrane.parse(self.code, "grid.membranes") | {"eb": eb})


def points(grid_block):
    """The grid points whose membrane carries bending (grid.membranes with eb)."""
    out = []
    for entry in grid_block.get("membranes", []):
        code = membrane.canonical(entry["membrane"], "grid.membranes")
        if "eb" in membrane.parse(code, "grid.membranes"):
            out.append(Point(float(entry["ca"]), float(entry["phi"]), code))
    return out


def moduli(block):
    """The further bending moduli of `eblimit.eb`, checked: 0 < eb <= 1, each once."""
    values = [float(eb) for eb in block["eb"]]
    for eb in values:
        if not 0 < eb <= 1:
            raise ValueError(f"eblimit.eb: {eb:g} is outside 0 < eb <= 1 (eb -> 0 is the "
                             "limit these runs extrapolate to, not a run)")
    return sorted(set(values))


def dilute_cases(block, grid_block):
    """(Ca, eb) of the dilute runs that measure the extrapolation's error: every Ca of the
    points at every modulus, the grid's own included."""
    cases = {(p.ca, eb) for p in points(grid_block) for eb in moduli(block) + [p.eb]}
    return sorted(cases)


def limit(eb, values, errors):
    """(the value at eb = 0, its standard error) of the least-squares line through
    (eb, values) weighted by 1/errors^2: exact for two moduli, linear in the values, so
    the error propagates exactly."""
    eb = np.asarray(eb, dtype=float)
    errors = np.asarray(errors, dtype=float)
    weights = 1.0 / errors if np.all(errors > 0) else None

    def intercept(v):
        return np.polynomial.polynomial.polyfit(eb, v, 1, w=weights)[0]

    values = np.asarray(values, dtype=float)
    return float(intercept(values)), float(propagated_standard_error(intercept, values,
                                                                     errors))


def relative_miss(dilute_rows, reference_row, q):
    """The relative miss of the extrapolation to eb = 0 for one capsule: (limit of its
    bending runs) / (its run without bending) - 1."""
    se = SE.get(q, f"{q}_se")
    value, _ = limit([r["eb"] for r in dilute_rows], [r[q] for r in dilute_rows],
                     [r[se] for r in dilute_rows])
    return value / reference_row[q] - 1.0


def point_row(point, runs, dilute_rows, reference_row):
    """One row: the point, its moduli and how far each run got, and per quantity the
    grid's value at its eb, the limit eb -> 0 with its standard error (statistical and
    model in quadrature), the model part and the correction limit / grid value - 1."""
    runs = sorted(runs, key=lambda r: r["eb"])
    eb = [r["eb"] for r in runs]
    row = {"ca": point.ca, "phi": point.phi, "membrane": point.code,
           "moduli": " ".join(f"{e:g}" for e in eb),
           "t_end": " ".join(f"{r['t_end']:.4g}" for r in runs),
           "ended": " ".join(r["ended"] for r in runs)}
    grid = next(r for r in runs if r["eb"] == point.eb)
    for q in QUANTITIES:
        se = SE.get(q, f"{q}_se")
        value, stat = limit(eb, [r[q] for r in runs], [r[se] for r in runs])
        model = abs(relative_miss(dilute_rows, reference_row, q) * value)
        row[f"{q}_eb"], row[f"{q}_eb_se"] = grid[q], grid[se]
        row[q], row[f"{q}_se"] = value, math.hypot(stat, model)
        row[f"{q}_model"] = model
        row[f"{q}_correction"] = value / grid[q] - 1.0
    return row


def table(grid_block, runs, t_start, dilute_start):
    """The study's table, one point_row per point of the grid's bending membranes.
    runs: {"case": "suspension", "dilute" or "reference" (the dilute study's run without
    bending), "ca", "phi", "eb", "folder"} of every run the study reads (the workflow
    lists them from their RunSpecs, so no folder name is spelt here). A suspension run
    averages from t_start to its last sample (a run that stopped early: to its stop, and
    `ended` says so); a dilute run from dilute_start."""
    def rows_of(case, **match):
        return [{**run_row(r["folder"], dilute_start if case != "suspension" else t_start),
                 "eb": r["eb"]}
                for r in runs if r["case"] == case
                and all(math.isclose(float(r[k]), v) for k, v in match.items())]

    out = []
    for point in points(grid_block):
        reference = rows_of("reference", ca=point.ca)
        if len(reference) != 1:
            raise ValueError(f"eblimit: Ca {point.ca:g} needs one dilute run without "
                             f"bending, got {len(reference)}")
        out.append(point_row(point, rows_of("suspension", ca=point.ca, phi=point.phi),
                             rows_of("dilute", ca=point.ca), reference[0]))
    return pd.DataFrame(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", required=True, help="config grid as JSON")
    ap.add_argument("--runs", required=True, help="the runs as JSON (table())")
    ap.add_argument("--t-start", type=float, required=True,
                    help="the suspensions' averages from here")
    ap.add_argument("--dilute-t-start", type=float, required=True,
                    help="the dilute runs' averages from here")
    ap.add_argument("--out-csv", required=True)
    ap.add_argument("--out-md", required=True)
    args = ap.parse_args(argv)
    out = table(json.loads(args.grid), json.loads(args.runs), args.t_start,
                args.dilute_t_start)
    write_table(args.out_csv, out)
    shown = ["ca", "phi", "membrane", "moduli", "ended"] + [
        c for q in QUANTITIES for c in (f"{q}_eb", q, f"{q}_se", f"{q}_correction")]
    Path(args.out_md).write_text(markdown_table(out[shown]) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

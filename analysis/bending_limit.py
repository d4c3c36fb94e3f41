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

With `eblimit.in_grid` the grid table itself carries these limits at the points
(paper_membrane()), so every figure, coefficient and claim reads the paper's membrane.

    python -m analysis.bending_limit table --grid JSON --runs JSON --t-start 10
        --dilute-t-start 10 --out-csv T.csv --out-md T.md
    python -m analysis.bending_limit grid --runs-table runs.csv --limits T.csv --out G.csv
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
from analysis.tables import markdown_table, run_row, stopped_row, write_table

QUANTITIES = ("D", "theta_D_deg", "mu_sp", "N1", "N2")  # those the table shows
SE = {"theta_D_deg": "theta_D_se_deg"}  # the standard error's column where not <q>_se
# Columns of a run row that are not averages of its series.
NOT_AVERAGES = {"ca", "phi", "capsules", "seed", "mesh_level", "t_start", "t_end", "count",
                "intrinsic", "volume_error_max", "eb"}
MISS_FLOOR = 10.0  # a dilute value within this many standard errors of 0 has no scale
# A point's limit needs every run averaged over at least this share of the grid's window
# (a run that stops a strain unit into it has an error of its own transient's size).
MIN_WINDOW = 0.5


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


def point_moduli(block, point, grid_block=None):
    """The further moduli of one point: `eblimit.eb`, and those `eblimit.more` gives it
    ({ca, phi, eb}: a stiffer run where the smaller modulus stops early). A `more` entry
    that names no point with bending (with grid_block given) is refused, naming it."""
    extra = []
    for entry in block.get("more", []):
        eb = float(entry["eb"])
        if not 0 < eb <= 1:
            raise ValueError(f"eblimit.more: eb {eb:g} is outside 0 < eb <= 1")
        at = (float(entry["ca"]), float(entry["phi"]))
        if grid_block is not None and not any(
                math.isclose(p.ca, at[0]) and math.isclose(p.phi, at[1])
                for p in points(grid_block)):
            raise ValueError(f"eblimit.more: Ca {at[0]:g} phi {at[1]:g} is not a grid "
                             "point with bending (grid.membranes)")
        if math.isclose(at[0], point.ca) and math.isclose(at[1], point.phi):
            extra.append(eb)
    return sorted(set(moduli(block) + extra) - {point.eb})


def dilute_cases(block, grid_block):
    """(Ca, eb) of the dilute runs that measure the extrapolation's error: every Ca of the
    points at every modulus it is run at, the grid's own included."""
    cases = {(p.ca, eb) for p in points(grid_block)
             for eb in point_moduli(block, p, grid_block) + [p.eb]}
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


def averaged_columns(row):
    """(column, its standard error's column) of every average of a run row
    (analysis.tables.COLUMNS): "D" with "D_se", "theta_D_deg" with "theta_D_se_deg"; the
    stresslet's components, which have none, with None."""
    out = []
    for column, value in row.items():
        if column in NOT_AVERAGES or not isinstance(value, (int, float)) or \
                "_se" in column:
            continue
        se = column[:-4] + "_se_deg" if column.endswith("_deg") else column + "_se"
        out.append((column, se if se in row else None))
    return out


def relative_miss(dilute_rows, reference_row, q, se):
    """The relative miss of the extrapolation to eb = 0 for one capsule: (limit of its
    bending runs) / (its run without bending) - 1; None where that run's value is within
    MISS_FLOOR standard errors of zero (a fluctuation of a steady capsule: no scale)."""
    reference = reference_row.get(q)
    scale = reference_row.get(se, 0.0) if se else 0.0
    if reference is None or not math.isfinite(reference) or \
            abs(reference) <= MISS_FLOOR * scale or reference == 0.0:
        return None
    value, _ = limit([r["eb"] for r in dilute_rows], [r[q] for r in dilute_rows],
                     [r[se] for r in dilute_rows] if se else [0.0] * len(dilute_rows))
    return value / reference - 1.0


def window_short(runs, min_window):
    """A sentence naming the runs whose averaging window is shorter than min_window
    strain units (they stopped early: a contact, or a fold at the smaller modulus), or
    "" when every run's is long enough."""
    short = [r for r in runs if not r["t_end"] - r["t_start"] >= min_window]
    return "; ".join(f"eb {r['eb']:g} stopped at {r['t_end']:.3g} ({r['ended']}), "
                     f"window under {min_window:g}" for r in short)


def point_row(point, runs, dilute_rows, reference_row, min_window=0.0):
    """One row: the point, the moduli whose runs carry it, how far each run got, and per
    average (every column of averaged_columns()) the grid's value at its eb, the limit
    eb -> 0 with its standard error (statistical and model in quadrature), the model part
    (the dilute miss of the same moduli's line; 0 where relative_miss() gives none) and
    the correction limit / grid value - 1. A run whose window is shorter than min_window
    is left out (`short` names it); with fewer than two runs left the point has no limit
    (NaN)."""
    runs = sorted(runs, key=lambda r: r["eb"])
    used = [r for r in runs if r["t_end"] - r["t_start"] >= min_window]
    eb = [r["eb"] for r in used]
    dilute_rows = [r for r in dilute_rows if any(math.isclose(r["eb"], e) for e in eb)]
    grid = next(r for r in runs if r["eb"] == point.eb)
    row = {"ca": point.ca, "phi": point.phi, "membrane": point.code,
           "moduli": " ".join(f"{e:g}" for e in eb),
           "t_end": " ".join(f"{r['t_end']:.4g}" for r in used),
           "ended": " ".join(r["ended"] for r in used),
           "window_end": min((r["t_end"] for r in used), default=math.nan),
           "volume_error_max": max((r.get("volume_error_max", math.nan) for r in used),
                                   default=math.nan),
           "short": window_short(runs, min_window)}
    for q, se in averaged_columns(grid):
        if len(used) >= 2:
            value, stat = limit(eb, [r[q] for r in used],
                                [r[se] for r in used] if se else [0.0] * len(used))
            miss = relative_miss(dilute_rows, reference_row, q, se)
        else:
            value, stat, miss = math.nan, math.nan, None
        model = abs(miss * value) if miss is not None else 0.0
        row[f"{q}_eb"] = grid[q]
        row[q], row[f"{q}_model"] = value, model
        row[f"{q}_correction"] = value / grid[q] - 1.0 if grid[q] else math.nan
        if se:
            row[f"{q}_eb_se"], row[se] = grid[se], math.hypot(stat, model)
    return row


def table(grid_block, runs, t_start, dilute_start):
    """The study's table, one point_row per point of the grid's bending membranes.
    runs: {"case": "suspension", "dilute" or "reference" (the dilute study's run without
    bending), "ca", "phi", "eb", "folder"} of every run the study reads (the workflow
    lists them from their RunSpecs, so no folder name is spelt here). A suspension run
    averages from t_start to its last sample (a run that stopped early: to its stop, and
    `ended` says so); a dilute run from dilute_start."""
    def row(folder, start):
        try:
            return run_row(folder, start)
        except ValueError:  # stopped before its averaging window: no averages
            return stopped_row(folder, start)

    def rows_of(case, **match):
        return [{**row(r["folder"], dilute_start if case != "suspension" else t_start),
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
                             rows_of("dilute", ca=point.ca), reference[0],
                             MIN_WINDOW * (grid_block["t_end"] - t_start)))
    return pd.DataFrame(out)


def paper_membrane(grid, limits):
    """The grid table (analysis.tables.COLUMNS) by the paper's membrane: the rows of the
    points that carry bending replaced by their limit eb -> 0 (table()), each average
    with its standard error, the membrane the paper's and `obtained` saying how (the
    other rows: "run"). Every figure, coefficient and claim read from it then compares
    the paper's model at every point."""
    out = grid.copy()
    out["obtained"] = "run"
    for limit_row in limits.to_dict("records"):
        if not math.isfinite(limit_row["D"]):
            continue  # no limit (limit_row["short"]): the point keeps its run with bending
        at = (np.isclose(out["ca"].astype(float), limit_row["ca"])
              & np.isclose(out["phi"].astype(float), limit_row["phi"])
              & (out["intrinsic"] == 0))
        for column in out.columns:
            if column in limit_row and column not in ("ca", "phi", "membrane", "t_end",
                                                      "ended"):
                out.loc[at, column] = limit_row[column]
        ended = [e for e in limit_row["ended"].split() if e != "t_end"]
        out.loc[at, "t_end"] = limit_row["window_end"]
        out.loc[at, "ended"] = ended[0] if ended else "t_end"
        out.loc[at, "membrane"] = membrane.PAPER
        out.loc[at, "obtained"] = f"eb -> 0 from eb {limit_row['moduli']}"
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    t = sub.add_parser("table", help="the limit eb -> 0 of every point with bending")
    t.add_argument("--grid", required=True, help="config grid as JSON")
    t.add_argument("--runs", required=True, help="the runs as JSON (table())")
    t.add_argument("--t-start", type=float, required=True,
                   help="the suspensions' averages from here")
    t.add_argument("--dilute-t-start", type=float, required=True,
                   help="the dilute runs' averages from here")
    t.add_argument("--out-csv", required=True)
    t.add_argument("--out-md", required=True)
    g = sub.add_parser("grid", help="the grid table with those points at their limit "
                       "(paper_membrane())")
    g.add_argument("--runs-table", required=True, help="the grid runs' table (CSV)")
    g.add_argument("--limits", required=True, help="the table of `table` (CSV)")
    g.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    if args.command == "grid":
        out = paper_membrane(pd.read_csv(args.runs_table), pd.read_csv(args.limits))
        write_table(args.out, out)
        return 0
    out = table(json.loads(args.grid), json.loads(args.runs), args.t_start,
                args.dilute_t_start)
    write_table(args.out_csv, out)
    shown = ["ca", "phi", "membrane", "moduli", "ended", "short"] + [
        c for q in QUANTITIES for c in (f"{q}_eb", q, SE.get(q, f"{q}_se"),
                                        f"{q}_correction")]
    Path(args.out_md).write_text(markdown_table(out[shown]) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

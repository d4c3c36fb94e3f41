"""Every checkable statement of the paper, against this run (and optionally another).

The claims are in config/paper_numbers.yaml: one entry per statement as the paper makes
it (its words, where it is made), with the test that reads it and how our side is computed
from the tables of a results folder. A claim's class says what it is and is counted apart:
`number` (a value, range or bound the paper states), `trend` (a statement over all the Ca
or phi it covers), `other-paper` (another study's number: the dilute anchors), `analytic`
(arithmetic the paper states, e.g. Krieger-Dougherty).

Verdicts (K = 2 standard errors; s our standard error, e the paper's own error where it
states one, never an error the paper does not state):

- value  v against the paper's p: agrees when |v - p| <= K sqrt(s^2 + e^2);
- range  v against [lo, hi] (a bound: `max`, lo = -inf): agrees when [v - K s, v + K s]
         meets [lo, hi];
- sign   agrees when v has the sign at >= K s from zero, differs at >= K s of the other;
- rises / falls  over every series (one per Ca, or per phi): differs when an adjacent step
         goes the other way by more than K of its combined standard errors; agrees when
         no step does and the weighted least-squares slope has the stated sign at >= K of
         its standard error;
- linear / nonlinear  the weighted straight-line fits of every series, pooled: chi^2 over
         the degrees of freedom; linear agrees when its chance exceeds that of K standard
         deviations (4.55 %), nonlinear when it does not;
- rounded  (analytic) agrees when our value rounds to the paper's at its stated precision;
- approx  an approximate equality with no stated tolerance: inconclusive, with the largest
         deviation, since no tolerance can be read from the paper.

A value, range or bound whose band K s is as wide as half the quantity itself (4 s >=
|p|: it could not tell the stated number from zero) is "inconclusive: needs" a standard
error below |p| / 4; a value with no standard error of ours is inconclusive too. A sign or
trend whose steps and slope are within K s of zero is inconclusive. A claim over several
points or series differs when any differs, agrees when all agree, and is inconclusive
otherwise. A claim made at another condition than ours (`not_comparable`, e.g. t_e 100
against our 30) is "not comparable" with why; a point of ours whose runs carry another
membrane than the paper's is left out of the claim, which says so. A claim this
configuration cannot give is "not in this configuration", with what is missing.

Computations (`ours.computation`), on the CSVs under the results folder; each gives points
(value, se, context) or series (x, y, se):

- value:      one row of `file` selected by `where` (several rows, e.g. seeds, are
              averaged with the standard error of the mean of runs); `phi: max` takes the
              largest phi there is.
- change:     y(to) - y(from) of `column` in the grid table at one Ca, each end a phi
              (`min`, `max`) or `dilute`; `relative: true` gives y(to) / y(from) - 1.
- every_row:  every row of `file` matching `where` as a point (column, se_column).
- series:     `y` against `x` in `file`, one series per value of `group` (rows matching
              `where`; `dilute: true` keeps the grid's dilute rows at phi = 0; `abs: true`
              takes |y|; `minus: {...}` subtracts another column or file matched on x and
              group).
- fit_slope_ratio: the relative change over the Ca range of the weighted line of `column`
              minus that of `than` (grid/fits.csv).
- spread:     the spread over initial positions (figure 11, Table 1): std / mean.
- mesh_error: eps of Table 1 at a mesh N_E against the finest mesh's mean.
- dilute:     the dilute table's value at its finest mesh level.
- dilute_relation: <S1 - S2> of each suspension point over the dilute limit's at the
              same <D> (interpolated between the dilute runs' Ca).

`each_ca: [..]` or `grid` on a claim makes one point per Ca ({ca} filled in); `points:`
lists several `ours` specs with their labels.

Usage: python -m analysis.paper_comparison --results results --numbers
       config/paper_numbers.yaml --out results/figures/paper_comparison [--label L]
       [--other DIR --other-label L]
Writes OUT.md, OUT.csv (one row per claim) and OUT_points.csv (one row per datum tested).
"""

import argparse
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from analysis import fits
from analysis.membrane import PAPER as PAPER_MEMBRANE
from analysis.statistics import mean_of_runs_standard_error, propagated_standard_error
from analysis.tables import markdown_table, read_yaml_list, select, with_data, write_table
from analysis.verdict import Missing, Results

K = 2.0  # the agreement band: 2 standard errors (95 % for a Gaussian)
CLASSES = ("number", "trend", "other-paper", "analytic")
POINT_TESTS = ("value", "range", "max", "sign", "rounded", "approx")
SERIES_TESTS = ("rises", "falls", "flat", "linear", "nonlinear")
TESTS = POINT_TESTS + SERIES_TESTS
AGREES, DIFFERS, INCONCLUSIVE = "agrees", "differs", "inconclusive"
NOT_COMPARABLE, NOT_HERE = "not comparable", "not in this configuration"
VERDICTS = (AGREES, DIFFERS, INCONCLUSIVE, NOT_COMPARABLE, NOT_HERE)


class NumbersError(ValueError):
    """A malformed claims file."""


class OtherCondition(Missing):
    """Our point is at another condition than the paper's (another membrane)."""


@dataclass
class Point:
    label: str
    value: float
    se: float
    context: str = ""
    paper: dict = field(default_factory=dict)  # the paper's value for this point, if own


@dataclass
class Series:
    label: str
    x: np.ndarray
    y: np.ndarray
    se: np.ndarray
    context: str = ""
    left_out: list = field(default_factory=list)  # points of another membrane
    paper: dict = field(default_factory=dict)


# ---------------------------------------------------------------- reading the tables


def _where_text(where):
    return ", ".join(f"{k} {v}" for k, v in where.items())


def _finite(x):
    return x is not None and not (isinstance(x, float) and math.isnan(x))


def _as_float(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def _rows(table, where, column, name):
    """The rows of `table` matching `where` that hold a value in `column`."""
    where = dict(where)
    phi_max = where.get("phi") == "max"
    if phi_max:
        del where["phi"]
    rows = select(table, **where)
    if "count" in rows:  # a run stopped before its averaging window has no averages
        stopped = rows[rows["count"] <= 0]
        rows = with_data(rows)
    else:
        stopped = rows.iloc[:0]
    if column not in rows:
        raise Missing(f"{name} has no column {column}")
    rows = rows[pd.to_numeric(rows[column], errors="coerce").notna()]
    if phi_max and not rows.empty:
        rows = rows[np.isclose(rows["phi"].astype(float), rows["phi"].astype(float).max())]
    if rows.empty:
        if not stopped.empty:
            r = stopped.iloc[0]
            raise Missing(f"the run at {_where_text(where)} stopped at t = "
                          f"{_as_float(r.get('t_end')):.3g} ({r.get('ended')}), before its "
                          "averaging window")
        raise Missing(f"no {name} row with {_where_text(where) or 'data'}")
    return rows


def _foreign(rows):
    """The membranes other than the paper's that these run rows carry (their column
    `membrane`; none where the table has no such column)."""
    if "membrane" not in rows:
        return []
    codes = rows["membrane"].astype(object).where(rows["membrane"].notna(), PAPER_MEMBRANE)
    return sorted(set(codes.astype(str)) - {PAPER_MEMBRANE})


def _excluded(rows, spec):
    """Rows without those of `exclude` ({column: value}, e.g. the rigid-sphere series)."""
    for key, unwanted in spec.get("exclude", {}).items():
        if key in rows:
            rows = rows[rows[key].astype(str) != str(unwanted)]
    return rows


def _in_ranges(rows, spec):
    """Rows within `where_range` ({column: [low, high]}, low <= v < high)."""
    for key, (low, high) in spec.get("where_range", {}).items():
        v = pd.to_numeric(rows[key], errors="coerce")
        rows = rows[(v >= low - 1e-12) & (v < high - 1e-12)]
    return rows


def _fit_foreign(res, ca, phi=None, phi_max=fits.FIT_PHI_MAX):
    """Membranes other than the paper's of the grid runs a coefficient of Ca `ca` was
    fitted from (0 < phi <= phi_max) and, for a share, of the run at `phi`."""
    grid = with_data(res.table("grid/table.csv"))
    at = np.isclose(grid["ca"].astype(float), ca) & (grid["intrinsic"] == 0)
    phis = grid["phi"].astype(float)
    used = at & ((phis <= phi_max + 1e-12) | (np.isclose(phis, phi) if phi is not None
                                              else False))
    return _foreign(grid[used])


def _paper_membrane_only(rows, where):
    """The rows, or OtherCondition when they carry another membrane than the paper's."""
    other = _foreign(rows)
    if other:
        raise OtherCondition(f"the run at {_where_text(where)} carries the membrane "
                             f"{', '.join(other)}, not the paper's")
    return rows


def _context(rows):
    """What produced these rows, in a few words: mesh, capsules, window."""
    parts = []
    if "mesh_level" in rows:
        levels = sorted({int(v) for v in rows["mesh_level"]})
        parts.append("N_E " + "/".join(str(20 * 4**lv) for lv in levels))
    if "capsules" in rows and "intrinsic" in rows and (rows["intrinsic"] == 0).any():
        parts.append("M " + "/".join(str(int(v)) for v in
                                     sorted(set(rows.loc[rows["intrinsic"] == 0, "capsules"]))))
    spans = sorted({f"{a:g}-{b:.3g}" for a, b in zip(rows.get("t_start", []),
                                                      rows.get("t_end", []))
                    if pd.notna(a) and pd.notna(b)})  # a mean row (Table 1's) has none
    if spans:
        parts.append("t " + "/".join(spans))
    if "seed" in rows and len(rows) > 1:
        parts.append(f"{len(rows)} runs")
    if "obtained" in rows and (rows["obtained"].fillna("run") != "run").any():
        parts.append("the paper's membrane as the limit eb -> 0")
    if "ended" in rows:
        early = rows[rows["ended"].fillna("t_end") != "t_end"]
        for r in early.itertuples():
            parts.append(f"stopped early at {r.t_end:.3g} ({r.ended})")
    return ", ".join(parts)


def _mean(rows, column, se_column):
    """Mean of the rows' values, and its standard error (that of the mean of independent
    runs; NaN where an error is missing)."""
    values = rows[column].astype(float).to_numpy()
    if se_column and se_column in rows:
        errors = rows[se_column].astype(float).to_numpy()
        se = float(errors[0]) if len(errors) == 1 else mean_of_runs_standard_error(errors)
    else:
        se = 0.0 if se_column == 0 else math.nan  # se_column 0: an exact value
    return float(values.mean()), se


# ---------------------------------------------------------------- point computations


def comp_value(res, spec):
    rows = _rows(res.table(spec["file"]), spec.get("where", {}), spec["column"],
                 spec["file"])
    for key, unwanted in spec.get("exclude", {}).items():  # e.g. Table 1's mean row
        rows = rows[rows[key].astype(str) != str(unwanted)]
    if rows.empty:
        raise Missing(f"no {spec['file']} row with {_where_text(spec.get('where', {}))}")
    _paper_membrane_only(rows, spec.get("where", {}))
    value, se = _mean(rows, spec["column"], spec.get("se_column"))
    return [Point("", value, se, _context(rows))]


def _grid_rows_at(res, spec, end):
    """The grid rows of spec["column"] at one end of a `change` (a phi, min, max or
    dilute), and that end."""
    table = res.table(spec.get("file", "grid/table.csv"))
    where = dict(spec.get("where", {}))
    column = spec["column"]
    if "ca" in where and select(table, ca=where["ca"]).empty:
        cas = ", ".join(f"{v:g}" for v in sorted(set(table["ca"].astype(float))))
        raise Missing(f"Ca {where['ca']:g} is not in this grid (Ca {cas})")
    if isinstance(end, (int, float)) and select(table, **where, phi=float(end)).empty:
        phis = ", ".join(f"{v:g}" for v in sorted(set(select(table, **where)["phi"])))
        raise Missing(f"phi {end:g} is not in this grid at {_where_text(where)} (phi {phis})")
    if end == "dilute":
        return _rows(table, {**where, "intrinsic": 1}, column, "grid (dilute)"), end
    susp = select(table, **where, intrinsic=0)
    phis = sorted(set(with_data(susp)["phi"].astype(float))) if "count" in susp \
        else sorted(set(susp["phi"].astype(float)))
    if end in ("min", "max"):
        if not phis:
            raise Missing(f"no suspension row with {_where_text(where)}")
        end = phis[0] if end == "min" else phis[-1]
    where = {**where, "phi": float(end), "intrinsic": 0}
    return _paper_membrane_only(_rows(table, where, column, "grid"), where), end


def comp_change(res, spec):
    r0, e0 = _grid_rows_at(res, spec, spec["from"])
    r1, e1 = _grid_rows_at(res, spec, spec["to"])
    (y0, s0), (y1, s1) = (_mean(r, spec["column"], spec.get("se_column")) for r in (r0, r1))
    if spec.get("relative"):
        value = y1 / y0 - 1.0
        se = propagated_standard_error(lambda v: v[1] / v[0] - 1.0, [y0, y1], [s0, s1])
    else:
        value, se = y1 - y0, math.hypot(s0, s1)
    ends = f"phi {'0 (dilute)' if e0 == 'dilute' else f'{e0:g}'} to {e1:g}"
    return [Point("", value, se, ends + "; " + _context(pd.concat([r0, r1])))]


def _label(row, keys):
    return ", ".join(f"{k} {_as_float(row[k]):g}" if _finite(_as_float(row[k]))
                     else f"{k} {row[k]}" for k in keys if k in row)


def comp_every_row(res, spec):
    """Every row matching `where` (and `where_range`) as a point, labelled by `label`
    (columns), less the value of `minus` (a `value` spec) where given; rows of another
    membrane (`grid_membrane`: also those a coefficient was fitted from) are left out,
    and the claim names them."""
    rows = _rows(res.table(spec["file"]), spec.get("where", {}), spec["column"],
                 spec["file"])
    rows = _in_ranges(_excluded(rows, spec), spec)
    offset, offset_se = 0.0, 0.0
    if "minus" in spec:
        (m,) = comp_value(res, spec["minus"])
        offset, offset_se = m.value, (m.se if _finite(m.se) else 0.0)
    points = []
    for _, r in rows.iterrows():
        other = [] if spec.get("any_membrane") else _foreign(r.to_frame().T)
        if spec.get("grid_membrane"):
            other = sorted(set(other) | set(_fit_foreign(
                res, float(r["ca"]), float(r.get("phi", math.nan)),
                float(spec.get("phi_max", fits.FIT_PHI_MAX)))))
        if spec.get("se_column") == 0:
            se = 0.0
        elif spec.get("se_column"):
            se = math.hypot(_as_float(r.get(spec["se_column"])), offset_se)
        else:
            se = math.nan
        point = Point(_label(r, spec.get("label", ["ca", "phi"])),
                      float(r[spec["column"]]) - offset, se)
        if other:
            point.context = "left out: membrane " + ", ".join(other)
        points.append(point)
    if not points:
        raise Missing(f"no {spec['file']} row with {_where_text(spec.get('where', {}))}")
    return points


def comp_spread(res, spec):
    column = spec["column"]
    table = res.table(spec["file"])
    rows = _rows(table, {"seed": "mean", **spec.get("where", {})}, column, spec["file"])
    r = rows.iloc[0]
    if "cases" in r and _finite(_as_float(r["cases"])):
        n = int(r["cases"])
    else:  # Table 1: the cases are the other rows at the reference's mesh
        n = int(((table["N_E"] == r["N_E"]) & (table["seed"].astype(str) != "mean")).sum())
    if n < 2:
        raise Missing(f"fewer than two initial positions in {spec['file']}")
    value = float(r[column + "_std"]) / float(r[column])
    when = f" at t_e = {float(r['t_e']):.3g}" if "t_e" in r else ""
    return [Point("", value, value / math.sqrt(2.0 * (n - 1)), f"{n} cases{when}")]


def comp_mesh_error(res, spec):
    table = res.table(spec["file"])
    n_e = int(spec["N_E"])
    finest = int(pd.to_numeric(table["N_E"]).max())
    if n_e == finest:
        raise Missing(f"N_E {n_e} is this configuration's reference (finest) mesh")
    if n_e not in set(pd.to_numeric(table["N_E"]).astype(int)):
        raise Missing(f"no N_E {n_e} (meshes: "
                      f"{', '.join(str(v) for v in sorted(set(table['N_E'].astype(int))))})")
    rows = table[(pd.to_numeric(table["N_E"]).astype(int) == n_e)
                 & (table["seed"].astype(str) != "mean")]
    ref = table[table["seed"].astype(str) == "mean"].iloc[0]
    q = spec["quantity"]  # D or mu_sp; eps = |x - ref| / ref (eqs. A1, A2)
    x, sx = _mean(rows, q, q + "_se")
    r, sr = float(ref[q]), _as_float(ref.get(q + "_se"))
    value = abs(x - r) / r
    # The error of x / r, as in Table 1: differences across the kink of |.| would shrink it.
    se = propagated_standard_error(lambda v: v[0] / v[1], [x, r], [sx, sr])
    return [Point(spec.get("label", ""), value, se, f"against our N_E {finest} mean")]


def comp_dilute(res, spec):
    table = res.table(spec.get("file", "dilute/table.csv"))
    rows = select(table, **spec["where"])
    if rows.empty:
        raise Missing(f"no dilute run at {_where_text(spec['where'])}")
    row = rows.iloc[0]
    levels = sorted((int(c.split("_")[1]) for c in row.index
                     if c.startswith("level_") and not c.endswith("_se")
                     and _finite(_as_float(row[c]))), reverse=True)
    if not levels:
        raise Missing(f"no dilute value at {_where_text(spec['where'])}")
    lv = levels[0]
    return [Point("", float(row[f"level_{lv}"]), _as_float(row.get(f"level_{lv}_se")),
                  f"level {lv} (N_E {20 * 4**lv})")]


def comp_dilute_relation(res, spec):
    """<S1 - S2> of every suspension point of the grid over the dilute limit's at the same
    <D>, minus 1: the dilute relation is the line through the dilute runs' (D, S1 - S2)
    over Ca; points outside its D range are left out (no extrapolation)."""
    table = with_data(res.table("grid/table.csv"))
    dilute = table[table["intrinsic"] == 1].sort_values("D")
    if len(dilute) < 2:
        raise Missing("fewer than two dilute runs in the grid")
    d, p = dilute["D"].to_numpy(float), dilute["principal_diff"].to_numpy(float)
    points = []
    for _, r in table[table["intrinsic"] == 0].iterrows():
        if not d[0] <= r["D"] <= d[-1]:
            continue
        ref = float(np.interp(r["D"], d, p))
        point = Point(_label(r, ["ca", "phi"]), r["principal_diff"] / ref - 1.0,
                      r["principal_diff_se"] / ref)
        if _foreign(r.to_frame().T):
            point.context = "left out: membrane " + ", ".join(_foreign(r.to_frame().T))
        points.append(point)
    if not points:
        raise Missing("no suspension point within the dilute runs' range of <D>")
    return points


# ---------------------------------------------------------------- series computations


def _series_rows(res, spec, file=None, column=None, se_column=None):
    table = res.table(file or spec["file"])
    rows = select(table, **spec.get("where", {}))
    if "count" in rows:
        rows = with_data(rows)
    rows = _in_ranges(_excluded(rows, spec), spec)
    if "intrinsic" in rows and not spec.get("dilute"):
        rows = rows[rows["intrinsic"] == 0]
    column = column or spec["y"]
    if column not in rows:
        raise Missing(f"{file or spec['file']} has no column {column}")
    rows = rows[pd.to_numeric(rows[column], errors="coerce").notna()]
    se_column = se_column or spec.get("se")
    if se_column == "of_std":  # a standard deviation of n cases: its error, 1/sqrt(2 (n-1))
        rows = rows.assign(_se=rows[column] / np.sqrt(2.0 * (rows["cases"] - 1)))
        se_column = "_se"
    return rows, column, se_column


def _averaged(rows, x, group, column, se_column):
    """{(group, x): (y, se, membranes other than the paper's)}, seeds averaged."""
    out = {}
    for key, g in rows.groupby([group, x] if group else [x], sort=True):
        key = key if isinstance(key, tuple) else (key,)
        y, se = _mean(g, column, se_column)
        out[(float(key[0]) if group else None, float(key[-1]))] = (y, se, _foreign(g))
    return out


def comp_series(res, spec):
    """One series of spec["y"] against spec["x"] per value of spec["group"]."""
    x, group = spec["x"], spec.get("group")
    rows, column, se_column = _series_rows(res, spec)
    data = _averaged(rows, x, group, column, se_column)
    if "minus" in spec:  # another quantity matched on (group, x)
        m = {**spec, **spec["minus"]}
        mrows, mcol, mse = _series_rows(res, m, m["file"], m["y"], m.get("se"))
        other = _averaged(mrows, x, group, mcol, mse)
        data = {k: (y - other[k][0], math.hypot(s, other[k][1]), f + other[k][2])
                for k, (y, s, f) in data.items() if k in other}
    if spec.get("grid_membrane"):  # coefficients fitted over phi <= phi_max of the grid
        data = _with_grid_membranes(res, data, spec)
    out = []
    for g in sorted({k[0] for k in data}, key=lambda v: (v is None, v)):
        keys = sorted(k for k in data if k[0] == g)
        kept = [k for k in keys if not data[k][2]]
        left = [f"{x} {k[1]:g} ({', '.join(data[k][2])})" for k in keys if data[k][2]]
        y = np.array([data[k][0] for k in kept])
        if spec.get("abs"):
            y = np.abs(y)
        label = f"{group} {g:g}" if group else "all"
        out.append(Series(label, np.array([k[1] for k in kept]), y,
                          np.array([data[k][1] for k in kept]), left_out=left))
    if not out:
        raise Missing(f"no {spec['file']} rows with {_where_text(spec.get('where', {}))}")
    return out


def _with_grid_membranes(res, data, spec):
    """Mark a coefficient (x or group: Ca) or a share (the other: phi) as of another
    membrane where a grid run it was computed from carries one."""
    phi_max = float(spec.get("phi_max", fits.FIT_PHI_MAX))
    out = {}
    for (g, xv), (y, se, f) in data.items():
        ca, phi = (xv, g) if spec["x"] == "ca" else (g, xv)
        extra = _fit_foreign(res, ca, phi, phi_max)
        out[(g, xv)] = (y, se, sorted(set(f) | set(extra)))
    return out


def comp_slopes(res, spec):
    """The weighted least-squares slope of y against x of every series (comp_series, the
    points of another membrane left out), as one series against the group (e.g. d<D>/dphi
    against Ca, figure 3)."""
    series = [s for s in comp_series(res, spec) if len(s.x) >= 2]
    if len(series) < 2:
        raise Missing("fewer than two series with two points of the paper's membrane")
    fitted = [fits.linear_fit(s.x, s.y, _weights(s.se)) for s in series]
    left = [f"{s.label}: {', '.join(s.left_out)}" for s in series if s.left_out]
    return [Series("slopes", np.array([float(s.label.split()[-1]) for s in series]),
                   np.array([f[1] for f in fitted]), np.array([f[2] for f in fitted]),
                   left_out=left)]


def comp_fit_slope_ratio(res, spec):
    """How much faster `column` falls than `than` over the Ca range: the weighted line of
    each, as its change over the range relative to its value at the smallest Ca, the
    first minus the second (negative: `column` falls faster)."""
    s = {**spec, "x": "ca", "group": None, "grid_membrane": True}
    a = comp_series(res, {**s, "y": spec["column"], "se": spec["column"] + "_se"})[0]
    b = comp_series(res, {**s, "y": spec["than"], "se": spec["than"] + "_se"})[0]
    if len(a.x) < 2 or len(b.x) < 2:
        raise Missing("fewer than two Ca")

    def relative_fall(x, v):
        intercept, slope, _ = fits.linear_fit(x, v)
        return slope * (x[-1] - x[0]) / (intercept + slope * x[0])

    def stat(v):
        return relative_fall(a.x, v[:len(a.x)]) - relative_fall(b.x, v[len(a.x):])

    values = np.concatenate([a.y, b.y])
    errors = np.concatenate([a.se, b.se])
    left = sorted(set(a.left_out) | set(b.left_out))
    context = f"Ca {a.x[0]:g} to {a.x[-1]:g}" + (f"; left out: {'; '.join(left)}"
                                                  if left else "")
    return [Point("", float(stat(values)), float(propagated_standard_error(stat, values, errors)),
                  context)]


COMPUTATIONS = {"value": comp_value, "change": comp_change, "every_row": comp_every_row,
                "spread": comp_spread, "mesh_error": comp_mesh_error,
                "dilute": comp_dilute, "dilute_relation": comp_dilute_relation,
                "series": comp_series, "slopes": comp_slopes,
                "fit_slope_ratio": comp_fit_slope_ratio}


# ---------------------------------------------------------------- claims


def _fill(obj, ca):
    """`obj` with "{ca}" in its strings replaced and a where-value "{ca}" made the number."""
    if isinstance(obj, dict):
        return {k: _fill(v, ca) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_fill(v, ca) for v in obj]
    if obj == "{ca}":
        return ca
    if isinstance(obj, str):
        return obj.replace("{ca}", f"{ca:g}")
    return obj


def load_numbers(path):
    """The list of claims of a claims file, validated."""
    _, claims = read_yaml_list(path, "claims", NumbersError)
    ids = set()
    for c in claims:
        where = f"{path}: claim {c.get('id', '(no id)')}"
        for key in ("id", "class", "quantity", "quote", "stated", "test"):
            if key not in c:
                raise NumbersError(f"{where}: missing '{key}'")
        if "ours" not in c and "points" not in c:
            raise NumbersError(f"{where}: needs 'ours' or 'points'")
        if c["class"] not in CLASSES:
            raise NumbersError(f"{where}: class must be one of {CLASSES}")
        if c["test"] not in TESTS:
            raise NumbersError(f"{where}: test must be one of {TESTS}")
        needs = {"value": ("value",), "rounded": ("value", "precision"), "max": ("value",),
                 "range": ("low", "high"), "sign": ("sign",)}.get(c["test"], ())
        for key in needs:
            if c.get(key) is None:
                raise NumbersError(f"{where}: a {c['test']} claim needs '{key}'")
        if c.get("error") and not c.get("error_is"):
            raise NumbersError(f"{where}: an 'error' needs 'error_is' (where the paper "
                               "states it)")
        specs = [c["ours"]] if "ours" in c else [p["ours"] for p in c["points"]]
        for spec in specs:
            if spec.get("computation") not in COMPUTATIONS:
                raise NumbersError(f"{where}: ours.computation must be one of "
                                   f"{sorted(COMPUTATIONS)}")
        if c["id"] in ids:
            raise NumbersError(f"{where}: duplicate id")
        ids.add(c["id"])
    return claims


def _grid_cas(results):
    try:
        grid = results.table("grid/table.csv")
    except Missing:
        return []
    return sorted(set(grid.loc[grid["intrinsic"] == 0, "ca"].astype(float)))


def point_specs(claim, results):
    """[(label, ours spec)] of a claim: its `points`, one per Ca (`each_ca`), or `ours`."""
    if "points" in claim:
        return [(p.get("label", ""), {**p["ours"], "_paper": {
            k: p[k] for k in ("value", "error", "low", "high", "needs_se_below") if k in p}})
            for p in claim["points"]]
    cas = claim.get("each_ca")
    if cas is None:
        return [("", claim["ours"])]
    cas = _grid_cas(results) if cas == "grid" else cas
    return [(f"Ca {ca:g}", _fill(claim["ours"], ca)) for ca in cas]


def check_requires(claim, results):
    """Raise Missing unless every `requires` entry ({file, where}) has a row: the study
    behind a claim is at the paper's parameters (Table 1: Ca 0.2, phi 0.3)."""
    for req in claim.get("requires", []):
        table = results.table(req["file"])
        if select(table, **req["where"]).empty:
            shown = {k: sorted(set(table[k].astype(float)))
                     for k in req["where"] if k in table}
            got = "; ".join(f"{k} {', '.join(f'{v:g}' for v in vs)}"
                            for k, vs in shown.items())
            raise Missing(f"{req['file']} is not at {_where_text(req['where'])}"
                          + (f" (it has {got})" if got else ""))


def evaluate(claim, results):
    """Our side of a claim: (points or series, what is missing or of another condition)."""
    check_requires(claim, results)
    data, missing = [], []
    for label, spec in point_specs(claim, results):
        try:
            got = COMPUTATIONS[spec["computation"]](results, spec)
        except OtherCondition as m:
            missing.append((label, str(m), True))
            continue
        except Missing as m:
            missing.append((label, str(m), False))
            continue
        except KeyError as k:  # a table of this configuration without that column
            missing.append((label, f"no column {k}", False))
            continue
        for item in got:
            item.paper = spec.get("_paper", {})
            if label:
                item.label = f"{label}, {item.label}" if item.label else label
            data.append(item)
    return data, missing


# ---------------------------------------------------------------- verdicts


@dataclass
class Verdict:
    word: str
    how: str
    z: float = 0.0  # how far off in combined standard errors (0 where none)


def interval_verdict(value, se, low, high, error=0.0, needs_below=None):
    """A value of ours (se) against [low, high] (the paper's number with its own `error`,
    a range or a bound), widened by K combined standard errors; inconclusive where our
    standard error is not below `needs_below`."""
    if not _finite(se):
        return Verdict(f"{INCONCLUSIVE}: needs a standard error of ours", "no SE")
    combined = math.hypot(se, error)
    off = low - value if value < low else value - high if value > high else 0.0
    sign = -1.0 if value < low else 1.0
    z = sign * off / combined if combined > 0 else (math.inf * sign if off else 0.0)
    how = (f"off by {sign * off:+.3g}" + (f" = {z:+.1f} combined SE" if combined > 0 else "")
           if off else "within")
    if off > K * combined:
        return Verdict(DIFFERS, how, z)
    if needs_below is not None and se >= needs_below:
        return Verdict(f"{INCONCLUSIVE}: needs a standard error below {needs_below:.2g}",
                       how + f"; SE {se:.2g}", z)
    return Verdict(AGREES, how, z)


def _needs_below(claim, scale):
    """The standard error below which a comparison can tell: the claim's own
    `needs_se_below`, else a quarter of the stated number (a +-2 SE band as wide as half
    of it)."""
    return float(claim.get("needs_se_below", abs(scale) / 4.0))


def point_verdict(claim, value, se):
    test = claim["test"]
    if test == "value":
        p = float(claim["value"])
        return interval_verdict(value, se, p, p, float(claim.get("error") or 0.0),
                                _needs_below(claim, p))
    if test == "range":
        lo, hi = float(claim["low"]), float(claim["high"])
        return interval_verdict(value, se, lo, hi, 0.0, _needs_below(claim, (lo + hi) / 2))
    if test == "max":
        b = float(claim["value"])
        return interval_verdict(value, se, -math.inf, b, 0.0, _needs_below(claim, b))
    if test == "rounded":
        step = float(claim["precision"])
        ok = math.isclose(round(value / step) * step, float(claim["value"]), abs_tol=step / 1e6)
        return Verdict(AGREES if ok else DIFFERS, f"{value:.4g} rounds to "
                       f"{round(value / step) * step:.4g} at {step:g}")
    if test == "approx":
        off = value - float(claim["value"])
        z = off / se if _finite(se) and se > 0 else math.nan
        return Verdict(f"{INCONCLUSIVE}: needs the tolerance of the paper's approximate "
                       "equality (none stated)", f"off by {off:+.3g}" +
                       (f" ({z:+.1f} SE)" if _finite(z) else ""), 0.0)
    want = 1.0 if claim["sign"] == "+" else -1.0  # sign
    if not _finite(se):
        return Verdict(f"{INCONCLUSIVE}: needs a standard error of ours", "no SE")
    z = value / se if se > 0 else math.inf * np.sign(value)
    how = f"{value:+.3g} ({z:+.1f} SE)" if math.isfinite(z) else f"{value:+.3g}"
    if want * z >= K:
        return Verdict(AGREES, how)
    if want * z <= -K:
        return Verdict(DIFFERS, how, abs(z))
    return Verdict(f"{INCONCLUSIVE}: needs a standard error below {abs(value) / K:.2g}", how)


def _weights(se):
    """The errors a weighted fit uses: an error below a millionth of the series' largest
    counts as that (a point known to round-off, e.g. a share the fit fixes, would make
    the fit singular); none where an error is missing."""
    se = np.asarray(se, dtype=float)
    if not np.all(np.isfinite(se)) or not np.any(se > 0):
        return None
    return np.maximum(se, 1e-6 * se.max())


def series_verdict(claim, s):
    """rises / falls / flat of one series: its adjacent steps and its weighted slope."""
    if len(s.x) < 2:
        return Verdict(f"{INCONCLUSIVE}: needs two points of the paper's membrane",
                       "fewer than two points")
    steps = np.diff(s.y)
    step_se = np.hypot(s.se[1:], s.se[:-1])
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(step_se > 0, steps / step_se, np.sign(steps) * math.inf)
    _, slope, slope_se = fits.linear_fit(s.x, s.y, _weights(s.se))
    # No error of the slope (errors missing): it cannot decide, zs NaN compares false.
    zs = slope / slope_se if _finite(slope_se) and slope_se > 0 else \
        math.inf * np.sign(slope) if slope_se == 0 else math.nan
    if claim["test"] == "flat":
        worst = int(np.argmax(np.abs(z)))
        change_se = slope_se * (s.x[-1] - s.x[0])
        how = (f"slope {slope:+.3g} ({zs:+.1f} SE); largest step {s.x[worst]:g} to "
               f"{s.x[worst + 1]:g}: {steps[worst]:+.3g} ({z[worst]:+.1f} SE)")
        if abs(z[worst]) >= K or abs(zs) >= K:
            return Verdict(DIFFERS, how, float(max(abs(z[worst]), abs(zs))))
        needs = claim.get("needs_se_below")
        if needs is not None and not change_se < float(needs):
            return Verdict(f"{INCONCLUSIVE}: needs a standard error of the change over the "
                           f"range below {float(needs):.2g}", how + f"; SE {change_se:.2g}")
        return Verdict(AGREES, how)
    want = 1.0 if claim["test"] == "rises" else -1.0
    worst = int(np.argmin(want * z))
    how = (f"slope {slope:+.3g} ({zs:+.1f} SE); least step {s.x[worst]:g} to "
           f"{s.x[worst + 1]:g}: {steps[worst]:+.3g} ({z[worst]:+.1f} SE)")
    if want * z[worst] <= -K:
        return Verdict(DIFFERS, how, abs(float(z[worst])))
    if want * zs >= K:
        return Verdict(AGREES, how)
    return Verdict(f"{INCONCLUSIVE}: needs a slope error below {abs(slope) / K:.2g}", how)


def linearity(series):
    """Pooled chi^2, degrees of freedom and its chance, of the weighted straight lines of
    the series with three or more points."""
    chi2, dof = 0.0, 0
    for s in series:
        se = _weights(s.se)
        if len(s.x) < 3 or se is None:
            continue
        intercept, slope, _ = fits.linear_fit(s.x, s.y, se)
        chi2 += float(np.sum(((s.y - intercept - slope * s.x) / se) ** 2))
        dof += len(s.x) - 2
    # scipy.stats is imported where used: the workflow imports this module at every
    # start (through pipeline.results_page), and scipy.stats takes about 1 s to import.
    from scipy import stats
    return chi2, dof, (float(stats.chi2.sf(chi2, dof)) if dof else math.nan)


def _combine(words):
    """A claim's verdict from those of its points or series."""
    if any(w == DIFFERS for w in words):
        return DIFFERS
    inconclusive = [w for w in words if w.startswith(INCONCLUSIVE)]
    if inconclusive:
        return inconclusive[0]
    return AGREES


def judge(claim, data):
    """(verdict, how, z, per-datum rows) of a claim over its points or series."""
    test = claim["test"]
    if test in ("linear", "nonlinear"):
        chi2, dof, p = linearity(data)
        if not dof:
            return f"{INCONCLUSIVE}: needs three points in a series", "", 0.0, []
        from scipy import stats  # imported where used, as in linearity()
        # Straight where the chance of the scatter is at least that of K standard
        # deviations (4.55 %).
        straight = p >= 2.0 * stats.norm.sf(K)
        word = AGREES if straight == (test == "linear") else DIFFERS
        z = float(stats.norm.isf(max(p, 1e-300) / 2.0))
        return word, f"chi^2 {chi2:.1f} over {dof} degrees of freedom, chance {p:.2g}", \
            (z if word == DIFFERS else 0.0), []
    verdicts = [series_verdict({**claim, **s.paper}, s) if test in ("rises", "falls", "flat")
                else point_verdict({**claim, **s.paper}, s.value, s.se) for s in data]
    word = _combine([v.word for v in verdicts])
    if len(data) == 1:
        return word, verdicts[0].how, verdicts[0].z, verdicts
    if test == "approx":  # no tolerance to judge by: the largest deviation, and how many
        worst = max(range(len(data)), key=lambda i: abs(data[i].value - claim["value"]))
        known = [d for d in data if _finite(d.se) and d.se > 0]
        beyond = sum(abs(d.value - claim["value"]) > K * d.se for d in known)
        count = (f"{beyond} of {len(known)} beyond 2 SE of exact" if known
                 else "no standard error of ours")
        return word, f"largest at {data[worst].label}: {verdicts[worst].how}; {count}", \
            0.0, verdicts
    z = max((abs(v.z) for v in verdicts if v.word == DIFFERS), default=0.0)
    shown = [f"{d.label}: {v.how}" for d, v in zip(data, verdicts)
             if v.word != AGREES or len(data) <= 3]
    counts = pd.Series([v.word.split(":")[0] for v in verdicts]).value_counts()
    head = ", ".join(f"{n} {w}" for w, n in counts.items()) + f" of {len(verdicts)}"
    return word, head + ("; " + "; ".join(shown) if shown else ""), z, verdicts


def paper_text(claim):
    test = claim["test"]
    if test == "sign":
        return {"+": "> 0", "-": "< 0"}[claim["sign"]]
    if test == "max":
        return f"<= {claim['value']:g}"
    if test == "range":
        return f"{claim['low']:g} to {claim['high']:g}"
    if test in SERIES_TESTS:
        return {"rises": "rises", "falls": "falls", "flat": "does not vary",
                "linear": "linear", "nonlinear": "nonlinear"}[test]
    # Points may state their own values and errors (Table 1's cases): the claim's, an
    # anchor's shared by all, would name another number of the paper.
    points = claim.get("points") or [{}]
    values = sorted({p.get("value", claim.get("value")) for p in points})
    errors = {p.get("error", claim.get("error")) for p in points}
    text = (f"{values[0]:g}" if len(values) == 1 else
            f"{len(points)} points, {values[0]:g} to {values[-1]:g}")
    if test == "approx":
        return "~ " + text
    error = errors.pop() if len(errors) == 1 else None
    return text + (f" +- {error:.2g}" if error else "")


def _fmt(value, se):
    digits = 4 if abs(value) >= 1e-3 or value == 0 else 3
    text = f"{value:.{digits}g}"
    return text + (f" +- {se:.2g}" if _finite(se) and se > 0 else "")


def _shown(data):
    if len(data) == 1 and isinstance(data[0], Point):
        return _fmt(data[0].value, data[0].se)
    if data and isinstance(data[0], Series):
        return f"{len(data)} series, {sum(len(s.x) for s in data)} points"
    values = [d.value for d in data]
    return f"{len(data)} points, {min(values):.3g} to {max(values):.3g}"


def _left_out(data, missing):
    """What the claim leaves out: points of another membrane, and those not here."""
    other = [f"{s.label}: {', '.join(s.left_out)}" for s in data
             if isinstance(s, Series) and s.left_out]
    other += [f"{d.label} ({d.context[len('left out: '):]})" for d in data
              if isinstance(d, Point) and d.context.startswith("left out")]
    other += [f"{label + ': ' if label else ''}{why}" for label, why, o in missing if o]
    absent = [f"{label + ': ' if label else ''}{why}" for label, why, o in missing if not o]
    parts = ([f"left out, another membrane than the paper's: {'; '.join(other)}"]
             if other else [])
    parts += [f"not in this configuration: {'; '.join(absent)}"] if absent else []
    return "; ".join(parts)


def compare_claim(claim, results):
    """One result row of a claim for one results folder (a dict), and its datum rows."""
    try:
        data, missing = evaluate(claim, results)
    except Missing as m:
        return {"value": math.nan, "se": math.nan, "shown": NOT_HERE, "verdict": NOT_HERE,
                "reason": str(m), "z": 0.0}, []
    minimum = 2 if claim["test"] in ("rises", "falls", "flat") else 3 \
        if claim["test"] in ("linear", "nonlinear") else 0
    for d in data:  # a series too short at the paper's condition is left out whole
        if isinstance(d, Series) and 0 < len(d.x) < minimum:
            d.left_out.append(f"only {len(d.x)} point(s) left")
    kept = [d for d in data if not (isinstance(d, Point) and d.context.startswith("left out"))
            and not (isinstance(d, Series) and len(d.x) < max(minimum, 1))]
    if not kept:
        other = [m for m in missing if m[2]]
        word = NOT_COMPARABLE if other or any(d.context.startswith("left out") for d in data
                                              if isinstance(d, Point)) else NOT_HERE
        return {"value": math.nan, "se": math.nan, "shown": word, "verdict": word,
                "reason": _left_out(data, missing) or "nothing to compare", "z": 0.0}, []
    word, how, z, verdicts = judge(claim, kept)
    if claim.get("not_comparable"):
        word, how = NOT_COMPARABLE, f"{claim['not_comparable']}; ours: {how}"
    contexts = sorted({d.context for d in kept if d.context})
    reason = "; ".join(p for p in [how, " / ".join(contexts) if len(contexts) == 1 else "",
                                   _left_out(data, missing)] if p)
    note = claim.get("if_differs") if word != AGREES else claim.get("if_agrees")
    if note:
        reason += f"; {note}"
    single = len(kept) == 1 and isinstance(kept[0], Point)
    row = {"value": kept[0].value if single else math.nan,
           "se": kept[0].se if single else math.nan, "shown": _shown(kept),
           "verdict": word, "reason": reason, "z": z}
    return row, _datum_rows(claim, kept, verdicts, word)


def _datum_rows(claim, data, verdicts, word):
    """The data a claim's verdict rests on: one row per value (a series one per x)."""
    rows = []
    for i, d in enumerate(data):
        v = verdicts[i].word.split(":")[0] if i < len(verdicts) else ""
        if isinstance(d, Series):
            rows += [{"id": claim["id"], "datum": f"{d.label}, x {x:g}", "value": y,
                      "se": s, "datum_verdict": v, "claim_verdict": word}
                     for x, y, s in zip(d.x, d.y, d.se)]
        else:
            rows.append({"id": claim["id"], "datum": d.label, "value": d.value, "se": d.se,
                         "datum_verdict": v, "claim_verdict": word})
    return rows


def comparison_tables(claims, results, other=None):
    """(claims table, datum table) as DataFrames: one row per claim with the paper's side,
    this run's value, verdict, reason and distance in combined SE (and the same for
    `other`, a Results, when given); one row per datum tested."""
    out, data = [], []
    for c in claims:
        ours, datum_rows = compare_claim(c, results)
        data += datum_rows
        row = {"id": c["id"], "class": c["class"], "quantity": c["quantity"],
               "quote": c["quote"], "stated": c["stated"], "test": c["test"],
               "paper": paper_text(c), "paper_error_is": c.get("error_is", ""),
               "this_run": ours["shown"], "this_value": ours["value"],
               "this_se": ours["se"], "this_verdict": ours["verdict"],
               "this_reason": ours["reason"], "this_z": ours["z"]}
        if other is not None:
            theirs, _ = compare_claim(c, other)
            row.update({"other": theirs["shown"], "other_value": theirs["value"],
                        "other_se": theirs["se"], "other_verdict": theirs["verdict"],
                        "other_reason": theirs["reason"]})
        out.append(row)
    columns = ["id", "datum", "value", "se", "datum_verdict", "claim_verdict"]
    return pd.DataFrame(out), pd.DataFrame(data, columns=columns)


def comparison_table(claims, results, other=None):
    """The claims table alone (comparison_tables)."""
    return comparison_tables(claims, results, other)[0]


def verdict_counts(table, column="this_verdict"):
    """{class: {verdict: count}} (an inconclusive counted as such, whatever it needs)."""
    words = table[column].str.split(":").str[0]
    return {c: words[table["class"] == c].value_counts().to_dict() for c in CLASSES}


def counts_line(table, label, column="this_verdict"):
    names = {"number": "numbers", "trend": "trends", "other-paper": "other papers",
             "analytic": "analytic"}
    parts = []
    for c, counts in verdict_counts(table, column).items():
        n = sum(counts.values())
        if n:
            parts.append(f"{names[c]}: " + ", ".join(
                f"{counts.get(w, 0)} {w}" for w in VERDICTS if counts.get(w, 0))
                + f" of {n}")
    return f"{label}: " + "; ".join(parts) + "."


RULE = ("Rule (analysis/paper_comparison.py): a number agrees when it lies within the "
        "paper's stated error or range, widened by 2 of our standard errors (combined in "
        "quadrature with the paper's own error where it states one: Table 1's spread of "
        "its three N_E 5120 cases); no error the paper does not state is assumed. Where "
        "the +-2 SE band is as wide as half the stated number, or we have no standard "
        "error, the verdict is inconclusive with what it needs. A trend is tested on "
        "every series it covers: it differs when an adjacent step goes the other way by "
        "more than 2 combined SE, agrees when none does and the weighted slope has the "
        "stated sign at 2 SE; linearity by the pooled chi^2 of straight lines (chance "
        "4.55 %). An approximate equality without a stated tolerance is inconclusive. A "
        "claim over several points or series differs when any differs and agrees when all "
        "agree. Points whose runs carry another membrane than the paper's are left out "
        "and named; a claim made at another condition is not comparable. +-: our "
        "standard error of the time average (docs/conventions.md), propagated to first "
        "order through ratios and fits.")


def markdown(table, label, other_label=None):
    """The comparison as markdown: the table, the counts, the rule."""
    columns = ["quantity", "stated", "paper", "this_run", "this_verdict", "this_reason"]
    headers = ["claim", "where in the paper", "paper", f"this run ({label})", "verdict",
               "reason"]
    if "other" in table:
        columns += ["other", "other_verdict", "other_reason"]
        headers += [f"other ({other_label})", "verdict", "reason"]
    cells = table[columns].map(lambda v: str(v).replace("|", "/"))
    lines = [markdown_table(cells, headers=headers), "",
             counts_line(table, f"This run ({label})")]
    if "other" in table:
        lines.append(counts_line(table, f"Other ({other_label})", "other_verdict"))
    lines += ["", RULE]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description="The paper's claims against this run's.")
    ap.add_argument("--results", default="results", help="this run's results folder")
    ap.add_argument("--numbers", required=True, help="config/paper_numbers.yaml")
    ap.add_argument("--out", required=True,
                    help="output stem: writes OUT.md, OUT.csv and OUT_points.csv")
    ap.add_argument("--label", default="this configuration",
                    help="what produced this run's results (its configuration)")
    ap.add_argument("--other", help="a second results folder (another configuration)")
    ap.add_argument("--other-label", default=None, help="what produced --other")
    args = ap.parse_args(argv)
    try:
        claims = load_numbers(args.numbers)
    except NumbersError as err:
        print(f"paper_comparison: error: {err}", file=sys.stderr)
        return 2
    other = Results(args.other) if args.other else None
    table, data = comparison_tables(claims, Results(args.results), other)
    out = Path(args.out)
    write_table(out.with_suffix(".csv"), table)
    write_table(out.with_name(out.name + "_points.csv"), data)
    text = markdown(table, args.label, args.other_label or args.other)
    out.with_suffix(".md").write_text(text, encoding="utf-8")
    print(counts_line(table, args.label))
    return 0


if __name__ == "__main__":
    sys.exit(main())

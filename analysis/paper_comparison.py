"""Every number the paper states, against this run's value (and optionally another's).

The numbers are in config/paper_numbers.yaml: each with its value and error (or the sign of
a trend, or a bound), where the paper states it, and how our value is computed from the
tables of a results folder (`ours`: a named computation below, its file and row
selection). A row of the comparison gives the paper's number, our value +- its standard
error, the verdict and a short reason. The verdict (K_COMBINED = 2):

- value:  agrees when |ours - paper| <= 2 sqrt(se_ours^2 + se_paper^2);
- sign:   agrees when ours has the paper's sign and |ours| >= 2 se_ours; differs when it
          has the other sign at >= 2 se_ours; inconclusive when it is within 2 se_ours of 0;
- max:    agrees when ours - 2 se_ours <= the paper's bound (at most that value);
- a number our configuration cannot give (a Ca, phi or mesh it does not run, a run that
  stopped before its averaging window) is "not in this configuration", with what is
  missing, never an error.

Computations (`ours.computation`), all on the CSVs under the results folder:

- value:      one row of `file` selected by `where` (rows whose `column` is empty are
              skipped; several rows, e.g. seeds, are averaged, with the standard error of
              the mean of runs); `phi: max` in `where` takes the largest phi there is.
- change:     y(to) - y(from) of `column` in the grid table at one Ca (`where`), each end a
              phi (a number, `min` or `max` over phi > 0) or `dilute` (the dilute run of the
              grid, phi = 0); `relative: true` gives y(to) / y(from) - 1.
- ca_change:  the same along Ca in the table of coefficients (grid/fits.csv,
              analysis.coefficients):
              c(largest Ca) - c(smallest Ca), or relative.
- faster_fall: relative change of `column` minus that of `than` from the smallest to the
              largest Ca (negative: `column` falls faster).
- difference: value(a) - value(b), two `value` specs.
- spread:     the initial-position spread of figure 11 at its last t_e: the standard
              deviation of the cases over their mean, `column_std` / `column` (row
              seed = mean); its error that of a standard deviation of n normal samples,
              1 / sqrt(2 (n - 1)) relative.
- mesh_error: eps of Table 1 at a mesh N_E (the mean over that mesh's runs), unless N_E is
              the finest mesh of the study (then it is the reference, with no error).
- dilute:     the dilute table's value at the finest mesh level it holds.

`each_ca: [..]` repeats a number for each Ca listed (`{ca}` in its texts and `where`
filled in); `each_ca: grid` for each Ca of this run's grid table.

Usage: python -m analysis.paper_comparison --results results --numbers
       config/paper_numbers.yaml --out results/figures/paper_comparison [--label L]
       [--other DIR --other-label L]
Writes OUT.md and OUT.csv.
"""

import argparse
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.statistics import mean_of_runs_standard_error, propagated_standard_error
from analysis.tables import markdown_table, read_yaml_list, select, with_data, write_table
from analysis.verdict import Missing, Results, at_most, within

K_COMBINED = 2.0  # the agreement band: 2 combined standard errors (95 % for a Gaussian)
KINDS = ("value", "sign", "max")
NOT_HERE = "not in this configuration"


class NumbersError(ValueError):
    """A malformed numbers file."""


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


def _context(rows):
    """What produced these rows, in a few words: mesh, capsules, window."""
    parts = []
    if "mesh_level" in rows:
        levels = sorted({int(v) for v in rows["mesh_level"]})
        parts.append("N_E " + "/".join(str(20 * 4**lv) for lv in levels))
    if "capsules" in rows and "intrinsic" in rows and (rows["intrinsic"] == 0).any():
        parts.append("M " + "/".join(str(int(v)) for v in
                                     sorted(set(rows.loc[rows["intrinsic"] == 0, "capsules"]))))
    if "t_start" in rows and "t_end" in rows:
        parts.append("t " + "/".join(sorted({f"{a:g}-{b:.3g}" for a, b in
                                             zip(rows["t_start"], rows["t_end"])})))
    if "seed" in rows and len(rows) > 1:
        parts.append(f"{len(rows)} runs")
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
        se = math.nan
    return float(values.mean()), se


# ---------------------------------------------------------------- the computations


def comp_value(res, spec):
    rows = _rows(res.table(spec["file"]), spec.get("where", {}), spec["column"],
                 spec["file"])
    for key, unwanted in spec.get("exclude", {}).items():  # e.g. Table 1's mean row
        rows = rows[rows[key].astype(str) != str(unwanted)]
    if rows.empty:
        raise Missing(f"no {spec['file']} row with {_where_text(spec.get('where', {}))}")
    value, se = _mean(rows, spec["column"], spec.get("se_column"))
    return value, se, _context(rows)


def _grid_value(res, spec, end):
    """The value of spec["column"] at one end of a `change` (a phi, min, max or dilute)."""
    table = res.table(spec.get("file", "grid/table.csv"))
    where = dict(spec.get("where", {}))
    column, se_column = spec["column"], spec.get("se_column")
    if "ca" in where and select(table, ca=where["ca"]).empty:
        cas = ", ".join(f"{v:g}" for v in sorted(set(table["ca"].astype(float))))
        raise Missing(f"Ca {where['ca']:g} is not in this grid (Ca {cas})")
    if isinstance(end, (int, float)) and select(table, **where, phi=float(end)).empty:
        phis = ", ".join(f"{v:g}" for v in sorted(set(select(table, **where)["phi"])))
        raise Missing(f"phi {end:g} is not in this grid at {_where_text(where)} (phi {phis})")
    if end == "dilute":
        rows = _rows(table, {**where, "intrinsic": 1}, column, "grid (dilute)")
    else:
        susp = select(table, **where, intrinsic=0)
        phis = sorted(set(with_data(susp)["phi"].astype(float))) if "count" in susp \
            else sorted(set(susp["phi"].astype(float)))
        if end in ("min", "max"):
            if not phis:
                raise Missing(f"no suspension row with {_where_text(where)}")
            end = phis[0] if end == "min" else phis[-1]
        rows = _rows(table, {**where, "phi": float(end), "intrinsic": 0}, column, "grid")
    value, se = _mean(rows, column, se_column)
    return value, se, rows, end


def comp_change(res, spec):
    y0, s0, r0, e0 = _grid_value(res, spec, spec["from"])
    y1, s1, r1, e1 = _grid_value(res, spec, spec["to"])
    if spec.get("relative"):
        value = y1 / y0 - 1.0
        se = propagated_standard_error(lambda v: v[1] / v[0] - 1.0, [y0, y1], [s0, s1])
    else:
        value, se = y1 - y0, math.hypot(s0, s1)
    ends = f"phi {'0 (dilute)' if e0 == 'dilute' else f'{e0:g}'} to {e1:g}"
    return value, se, ends + "; " + _context(pd.concat([r0, r1]))


def _by_ca(res, spec):
    rows = select(res.table(spec["file"]), **spec.get("where", {}))
    rows = rows[pd.to_numeric(rows.get(spec["column"]), errors="coerce").notna()] \
        if spec["column"] in rows else rows.iloc[:0]
    if len(rows) < 2:
        raise Missing(f"fewer than two Ca in {spec['file']} ({_where_text(spec.get('where', {}))})")
    return rows.sort_values("ca", kind="stable")


def _relative_change(v):
    return v[1] / v[0] - 1.0


def comp_ca_change(res, spec):
    rows = _by_ca(res, spec)
    lo, hi = rows.iloc[0], rows.iloc[-1]
    c, s = spec["column"], spec.get("se_column", spec["column"] + "_se")
    ys = [float(lo[c]), float(hi[c])]
    ses = [_as_float(lo.get(s)), _as_float(hi.get(s))]
    if spec.get("relative"):
        value, se = _relative_change(ys), propagated_standard_error(_relative_change, ys, ses)
    else:
        value, se = ys[1] - ys[0], math.hypot(*ses)
    return value, se, f"Ca {lo['ca']:g} to {hi['ca']:g}"


def comp_faster_fall(res, spec):
    rows = _by_ca(res, spec)
    lo, hi = rows.iloc[0], rows.iloc[-1]
    a, b = spec["column"], spec["than"]
    values = [float(lo[a]), float(hi[a]), float(lo[b]), float(hi[b])]
    errors = [_as_float(r.get(k + "_se")) for k in (a, b) for r in (lo, hi)]

    def stat(v):
        return (v[1] / v[0] - 1.0) - (v[3] / v[2] - 1.0)

    return stat(values), propagated_standard_error(stat, values, errors), \
        f"Ca {lo['ca']:g} to {hi['ca']:g}"


def comp_difference(res, spec):
    a, sa, ca = comp_value(res, spec["a"])
    b, sb, _ = comp_value(res, spec["b"])
    return a - b, math.hypot(sa, sb), ca


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
    return value, value / math.sqrt(2.0 * (n - 1)), f"{n} cases{when}"


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
    return value, se, f"against our N_E {finest} mean"


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
    return float(row[f"level_{lv}"]), _as_float(row.get(f"level_{lv}_se")), \
        f"level {lv} (N_E {20 * 4**lv})"


COMPUTATIONS = {"value": comp_value, "change": comp_change, "ca_change": comp_ca_change,
                "faster_fall": comp_faster_fall, "difference": comp_difference,
                "spread": comp_spread, "mesh_error": comp_mesh_error, "dilute": comp_dilute}


# ---------------------------------------------------------------- numbers and verdicts


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
    """The list of numbers of a numbers file, validated."""
    _, numbers = read_yaml_list(path, "numbers", NumbersError)
    ids = set()
    for n in numbers:
        where = f"{path}: number {n.get('id', '(no id)')}"
        for key in ("id", "quantity", "stated", "kind", "ours"):
            if key not in n:
                raise NumbersError(f"{where}: missing '{key}'")
        if n["kind"] not in KINDS:
            raise NumbersError(f"{where}: kind must be one of {KINDS}")
        if n["kind"] == "sign" and n.get("sign") not in ("+", "-"):
            raise NumbersError(f"{where}: a sign number needs sign: '+' or '-'")
        if n["kind"] in ("value", "max") and n.get("value") is None:
            raise NumbersError(f"{where}: needs a 'value'")
        if n["kind"] == "value" and "error" not in n:
            raise NumbersError(f"{where}: needs 'error' (the paper's error or a reading "
                               "error) and 'error_is' (what it is)")
        if n["ours"].get("computation") not in COMPUTATIONS:
            raise NumbersError(f"{where}: ours.computation must be one of "
                               f"{sorted(COMPUTATIONS)}")
        if n["id"] in ids:
            raise NumbersError(f"{where}: duplicate id")
        ids.add(n["id"])
    return numbers


def expand(numbers, results):
    """The numbers with each_ca repeated per Ca (`grid`: the Ca of results' grid table)."""
    out = []
    for n in numbers:
        cas = n.get("each_ca")
        if cas is None:
            out.append(n)
            continue
        if cas == "grid":
            try:
                grid = results.table("grid/table.csv")
                cas = sorted(set(grid.loc[grid["intrinsic"] == 0, "ca"].astype(float)))
            except Missing:
                cas = []
            if not cas:
                out.append({**_fill({k: v for k, v in n.items() if k != "each_ca"}, 0.0),
                            "id": n["id"].replace("{ca}", "-each"),
                            "quantity": n["quantity"].replace("{ca}", "each Ca"),
                            "_missing": "no grid table"})
        for ca in cas:
            out.append({**_fill({k: v for k, v in n.items() if k != "each_ca"}, ca)})
    return out


def check_requires(number, results):
    """Raise Missing unless every `requires` entry ({file, where}) has a row: the study
    behind a number is at the paper's parameters (Table 1: Ca 0.2, phi 0.3)."""
    for req in number.get("requires", []):
        table = results.table(req["file"])
        if select(table, **req["where"]).empty:
            shown = {k: sorted(set(table[k].astype(float)))
                     for k in req["where"] if k in table}
            got = "; ".join(f"{k} {', '.join(f'{v:g}' for v in vs)}"
                            for k, vs in shown.items())
            raise Missing(f"{req['file']} is not at {_where_text(req['where'])}"
                          + (f" (it has {got})" if got else ""))


def evaluate(number, results):
    """(value, se, context) of our side of `number`; raises Missing."""
    if "_missing" in number:
        raise Missing(number["_missing"])
    check_requires(number, results)
    spec = number["ours"]
    return COMPUTATIONS[spec["computation"]](results, spec)


def verdict(number, value, se):
    """("agrees" | "differs" | "inconclusive", how far off, in words)."""
    se = se if _finite(se) else 0.0
    kind = number["kind"]
    if kind == "value":
        paper, paper_se = float(number["value"]), float(number["error"])
        band = math.hypot(se, paper_se)
        word = "agrees" if within(value, paper, se=band, k=K_COMBINED) else "differs"
        off = value - paper
        if band == 0:
            return word, f"off by {off:+.3g}"
        return word, f"off by {off:+.3g} = {off / band:+.1f} combined SE"
    if kind == "max":
        bound = float(number["value"])
        word = "agrees" if at_most(value, bound, se, K_COMBINED) else "differs"
        return word, f"{value:.3g} against at most {bound:g}"
    want = 1.0 if number["sign"] == "+" else -1.0
    if se == 0:
        z = math.inf * np.sign(value) if value != 0 else 0.0
    else:
        z = value / se
    if want * z >= K_COMBINED:
        word = "agrees"
    elif want * z <= -K_COMBINED:
        word = "differs"
    else:
        word = "inconclusive"
    zt = f"{z:+.1f} SE" if math.isfinite(z) else "no SE"
    return word, f"{'+' if value >= 0 else '-'} ({zt})"


def paper_text(number):
    kind = number["kind"]
    if kind == "sign":
        return {"+": "> 0", "-": "< 0"}[number["sign"]]
    if kind == "max":
        return f"<= {number['value']:g}"
    text = f"{number['value']:g}"
    return text + (f" +- {number['error']:.2g}" if number["error"] else "")


def _fmt(value, se):
    digits = 4 if abs(value) >= 1e-3 or value == 0 else 3
    text = f"{value:.{digits}g}"
    return text + (f" +- {se:.2g}" if _finite(se) and se > 0 else "")


def compare(numbers, results):
    """One dict per (expanded) number for one results folder: its value, se, verdict and
    reason (or NOT_HERE and what is missing)."""
    rows = []
    for n in expand(numbers, results):
        try:
            value, se, context = evaluate(n, results)
        except Missing as m:
            rows.append({"id": n["id"], "value": math.nan, "se": math.nan,
                         "shown": NOT_HERE, "verdict": NOT_HERE, "reason": str(m),
                         "_number": n})
            continue
        word, how = verdict(n, value, se)
        reason = f"{how}; {context}" if context else how
        note = n.get("if_differs") if word != "agrees" else n.get("if_agrees")
        if note:
            reason += f"; {note}"
        rows.append({"id": n["id"], "value": value, "se": se, "shown": _fmt(value, se),
                     "verdict": word, "reason": reason, "_number": n})
    return rows


def comparison_table(numbers, results, other=None):
    """The comparison as a DataFrame: one row per number, the paper's side, this run's
    value, verdict and reason, and the same for `other` (a Results) when given."""
    ours = compare(numbers, results)
    theirs = {r["id"]: r for r in compare(numbers, other)} if other is not None else None
    if theirs is not None:  # a number only the other has (a Ca of its grid): ours is absent
        known = {r["id"] for r in ours}
        ours += [{**t, "value": math.nan, "se": math.nan, "shown": NOT_HERE,
                  "verdict": NOT_HERE, "reason": "not in this run's grid"}
                 for t in theirs.values() if t["id"] not in known]
    out = []
    for r in ours:
        n = r["_number"]
        row = {"id": r["id"], "quantity": n["quantity"], "stated": n["stated"],
               "kind": n["kind"], "paper": paper_text(n),
               "paper_value": n.get("value", math.nan),
               "paper_error": n.get("error", math.nan),
               "paper_error_is": n.get("error_is", ""),
               "this_run": r["shown"], "this_value": r["value"], "this_se": r["se"],
               "this_verdict": r["verdict"], "this_reason": r["reason"]}
        if theirs is not None:
            t = theirs.get(r["id"], {"shown": NOT_HERE, "value": math.nan, "se": math.nan,
                                     "verdict": NOT_HERE, "reason": "no such row"})
            row.update({"other": t["shown"], "other_value": t["value"], "other_se": t["se"],
                        "other_verdict": t["verdict"], "other_reason": t["reason"]})
        out.append(row)
    return pd.DataFrame(out)


def markdown(table, label, other_label=None):
    """The comparison as markdown: the rule, the table, the counts."""
    columns = ["quantity", "stated", "paper", "this_run", "this_verdict", "this_reason"]
    headers = ["quantity", "where in the paper", "paper", f"this run ({label})", "verdict",
               "reason"]
    if "other" in table:
        columns += ["other", "other_verdict", "other_reason"]
        headers += [f"other ({other_label})", "verdict", "reason"]
    cells = table[columns].map(lambda v: str(v).replace("|", "/"))
    lines = [markdown_table(cells, headers=headers)]
    counts = table["this_verdict"].value_counts()
    lines += ["", f"This run ({label}): " + ", ".join(
        f"{counts.get(w, 0)} {w}" for w in ("agrees", "differs", "inconclusive", NOT_HERE))
        + f" of {len(table)} numbers."]
    lines += ["", "Rule: a value agrees when |ours - paper| <= 2 sqrt(se_ours^2 + "
              "se_paper^2); se_paper is the paper's error where it gives one (the standard "
              "deviation of its three cases), otherwise the rounding or reading error "
              "stated in config/paper_numbers.yaml. A sign agrees when ours has the "
              "paper's sign at >= 2 se_ours from zero, differs at >= 2 se_ours of the "
              "other sign, and is inconclusive in between. A bound agrees when ours - "
              "2 se_ours is within it. +-: our standard error of the time average (docs/"
              "conventions.md), propagated to first order through ratios and fits."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description="The paper's numbers against this run's.")
    ap.add_argument("--results", default="results", help="this run's results folder")
    ap.add_argument("--numbers", required=True, help="config/paper_numbers.yaml")
    ap.add_argument("--out", required=True, help="output stem: writes OUT.md and OUT.csv")
    ap.add_argument("--label", default="this configuration",
                    help="what produced this run's results (its configuration)")
    ap.add_argument("--other", help="a second results folder (another configuration)")
    ap.add_argument("--other-label", default=None, help="what produced --other")
    args = ap.parse_args(argv)
    try:
        numbers = load_numbers(args.numbers)
    except NumbersError as err:
        print(f"paper_comparison: error: {err}", file=sys.stderr)
        return 2
    other = Results(args.other) if args.other else None
    table = comparison_table(numbers, Results(args.results), other)
    out = Path(args.out)
    write_table(out.with_suffix(".csv"), table)
    text = markdown(table, args.label, args.other_label or args.other)
    out.with_suffix(".md").write_text(text, encoding="utf-8")
    print(text.splitlines()[-3])
    return 0


if __name__ == "__main__":
    sys.exit(main())

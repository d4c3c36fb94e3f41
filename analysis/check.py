"""Compare figure data (CSV) with expected values and tolerances (config/expected/*.yaml),
and the figure data and the paper comparison's datum table with the committed ones.

The paper's numbers are not expectations here: they are claims of the paper comparison
(config/paper_numbers.yaml, analysis.paper_comparison), the one place where figure data
meet the paper. What the check holds against the paper is that comparison, through its
committed datum table (COMPARISON in the folder `--committed`): the regenerated data must
equal the committed ones within round-off (ROUND_OFF_REL, ROUND_OFF_ABS) and every verdict
must be the same, so a changed datum or agreement fails the check until the committed
table changes with it, in review. The figure data themselves (the other CSVs of that
folder) are held against the regenerated ones the same way: the same rows and columns,
numbers within round-off, texts equal.

An expectations file is YAML:

    expectations:
      - id: dilute-mu-ca02               # unique name, shown in the report
        file: dilute/table.csv           # CSV, relative to the results folder
        where: {ca: 0.2, quantity: "[mu]"}  # selects exactly one row (all fields match)
        column: level_2                  # the value to check
        value: 2.036                     # expected value, with rel_tol and/or abs_tol,
        rel_tol: 0.01                    #   or min/max bounds instead of value
        source: reference-run            # analytic | reference-run
        provenance: "our level-4 dilute run, docs/dilute_limit.md"
        se_column: level_2_se            # optional: the standard error of the checked value
        value_se: 0.0                    # optional: the standard error of `value`

Every expectation must state where its value comes from (`source`: analytic or
reference-run, and `provenance`); a value copied from the same run it checks is not an
expectation.

Standard errors: where the checked value is a time average (its row has a standard-error
column, analysis.statistics) or the expected value comes from a run with a known standard
error, `se_column` and `value_se` give them. The difference of two independent averages
then has the standard error se = sqrt(se_column^2 + value_se^2), and the value passes
within max(tolerance, k se) (analysis.verdict): the tolerance (rel_tol/abs_tol) stays the
bound where it is the wider (it budgets the systematic differences, mesh and box, and in
the suspension expectations already the statistical spread: adding k se on top would
count the statistics twice), and k se takes over where the run is noisier than the
tolerance assumed, so a check does not fail on noise alone. k is the file's top-level `k`
(K_STANDARD_ERRORS = 3 when absent).

Usage:
    python -m analysis.check --results results --report R.md [config/expected/a.yaml ...]
        [--committed config/expected/quantitative]
Exit status 1 if any expectation fails or the committed data differ from the
regenerated ones, with one readable line per failure.
"""

import argparse
import math
import sys
from pathlib import Path

import pandas as pd

from analysis.tables import read_yaml_list, select
from analysis.verdict import Missing, Results, at_least, at_most, band, within

SOURCES = ("analytic", "reference-run")  # the paper's: config/paper_numbers.yaml
# Round-off of the analysis: the datum table is regenerated from the same run records by
# the same code, so it differs from the committed one only by the order of floating-point
# sums (numpy, pandas versions): ~1e-15 relative per operation, ~1e-12 after the fits and
# propagations. 1e-9 relative leaves room for that and stays four orders below our
# smallest relative standard error (7e-6, the dilute D at N_E 5120): a change of the
# science shows.
ROUND_OFF_REL = 1e-9
ROUND_OFF_ABS = 1e-12
COMPARISON = "paper_comparison_points.csv"  # the comparison's datum table
# A difference beyond 3 standard errors has a chance of 0.3 % for a Gaussian estimate (2.7
# standard errors, 0.6 %, with the estimator's 9 % low bias, analysis.statistics): a
# dozen expectations then fail on noise alone in fewer than one check in ten.
K_STANDARD_ERRORS = 3.0


class ExpectationError(ValueError):
    """An expectation file that is malformed (not a failed comparison)."""


def load_expectations(path):
    """The list of expectations in one YAML file, validated."""
    data, items = read_yaml_list(path, "expectations", ExpectationError)
    k = data.get("k", K_STANDARD_ERRORS)
    if isinstance(k, bool) or not isinstance(k, (int, float)) or not k > 0:
        raise ExpectationError(f"{path}: 'k' (standard errors) must be a positive number, "
                               f"got '{k}'")
    for i, e in enumerate(items):
        where = f"{path}: expectation {i} ({e.get('id', 'no id')})"
        for key in ("id", "file", "column", "source", "provenance"):
            if not e.get(key):
                raise ExpectationError(f"{where}: missing '{key}'")
        if e["source"] not in SOURCES:
            raise ExpectationError(f"{where}: source must be one of {SOURCES}, "
                                   f"got '{e['source']}' (a number of the paper is a "
                                   "claim of config/paper_numbers.yaml)")
        has_value = e.get("value") is not None and ("rel_tol" in e or "abs_tol" in e)
        has_bounds = "min" in e or "max" in e
        if not (has_value or has_bounds):
            raise ExpectationError(f"{where}: give 'value' with 'rel_tol'/'abs_tol', "
                                   "or 'min'/'max'")
        if ("se_column" in e or "value_se" in e) and not has_value:
            raise ExpectationError(f"{where}: 'se_column'/'value_se' need a 'value'")
        e.setdefault("where", {})
        e["_file"] = str(path)
        e["_k"] = float(k)
    return items


def check_one(e, results):
    """(ok, message) for one expectation against the tables of `results`
    (analysis.verdict.Results)."""
    path = results.folder / e["file"]
    label = f"{e['id']} [{e['source']}: {e['provenance']}]"
    try:
        rows = select(results.table(e["file"]), **e["where"])
    except Missing:
        return False, f"FAIL {label}: {path} does not exist"
    if len(rows) != 1:
        return False, (f"FAIL {label}: {len(rows)} rows of {path} match {e['where']} "
                       "(need exactly one)")
    got = rows.iloc[0].get(e["column"])
    if not pd.api.types.is_number(got) or isinstance(got, bool) or math.isnan(got):
        return False, f"FAIL {label}: column '{e['column']}' is '{got}', not a number"
    got = float(got)
    if e.get("value") is not None:
        want = float(e["value"])
        tol = max(float(e.get("abs_tol", 0.0)), float(e.get("rel_tol", 0.0)) * abs(want))
        se, k, stat = 0.0, 0.0, ""
        if "se_column" in e or "value_se" in e:
            se_got = rows.iloc[0].get(e["se_column"]) if "se_column" in e else 0.0
            if not pd.api.types.is_number(se_got) or isinstance(se_got, bool) \
                    or math.isnan(se_got):
                return False, (f"FAIL {label}: standard-error column '{e['se_column']}' is "
                               f"'{se_got}', not a number")
            se = math.hypot(float(se_got), float(e.get("value_se", 0.0)))
            k = e.get("_k", K_STANDARD_ERRORS)
            stat = f"; {k:g} SE = {k * se:.3g}, SE {se:.3g}"
        ok = within(got, want, tol, se, k)
        detail = (f"{e['column']} = {got:.6g}, expected {want:.6g} +- {band(tol, se, k):.3g} "
                  f"(off by {got - want:+.3g}{stat})")
    else:
        lo, hi = float(e.get("min", -math.inf)), float(e.get("max", math.inf))
        ok = at_least(got, lo) and at_most(got, hi)
        detail = f"{e['column']} = {got:.6g}, expected in [{lo:.6g}, {hi:.6g}]"
    where = ", ".join(f"{k}={v}" for k, v in e["where"].items())
    return ok, f"{'ok  ' if ok else 'FAIL'} {label}: {e['file']} ({where}): {detail}"


def _key(table):
    return table.assign(datum=table["datum"].fillna("")).set_index(["id", "datum"])


def _equal(a, b):
    if pd.isna(a) and pd.isna(b):
        return True
    if pd.isna(a) or pd.isna(b):
        return False
    return abs(a - b) <= max(ROUND_OFF_ABS, ROUND_OFF_REL * max(abs(a), abs(b)))


def check_comparison(regenerated, committed):
    """(number failed, report lines) of the regenerated datum table of the paper
    comparison against the committed one: the same data, each value and standard error
    equal within round-off, and the same verdicts."""
    new, old = _key(pd.read_csv(regenerated)), _key(pd.read_csv(committed))
    lines, failed = [], 0
    for key in old.index.difference(new.index):
        lines.append(f"FAIL comparison {key[0]} [{key[1]}]: in {committed}, not regenerated")
    for key in new.index.difference(old.index):
        lines.append(f"FAIL comparison {key[0]} [{key[1]}]: regenerated, not in {committed}")
    failed += len(lines)
    for key in new.index.intersection(old.index):
        a, b = new.loc[key], old.loc[key]
        if isinstance(a, pd.DataFrame):  # a duplicated datum: compare it row by row
            a, b = a.iloc[0], b.iloc[0]
        diffs = [f"{c} {float(a[c])!r}, committed {float(b[c])!r}" for c in ("value", "se")
                 if not _equal(float(a[c]), float(b[c]))]
        diffs += [f"{c} '{a[c]}', committed '{b[c]}'" for c in
                  ("datum_verdict", "claim_verdict") if str(a[c]) != str(b[c])]
        if diffs:
            failed += 1
            lines.append(f"FAIL comparison {key[0]} [{key[1]}]: " + "; ".join(diffs))
    n = len(new)
    lines.append(f"{'ok  ' if not failed else 'FAIL'} comparison: {n - failed} of {n} data "
                 f"of {regenerated} as committed in {committed} (values within "
                 f"{ROUND_OFF_REL:g} relative, verdicts equal)")
    return failed, lines


def _differing_cells(new, old):
    """[(row, column, new, old)] of two tables of the same shape: numbers beyond
    round-off, anything else as text."""
    out = []
    for column in old.columns:
        a, b = new[column], old[column]
        if pd.api.types.is_numeric_dtype(a) and pd.api.types.is_numeric_dtype(b):
            bad = [i for i, (x, y) in enumerate(zip(a, b)) if not _equal(x, y)]
        else:
            text = [c.astype(object).where(c.notna(), "").astype(str) for c in (a, b)]
            bad = [i for i, (x, y) in enumerate(zip(*text)) if x != y]
        out += [(i, column, a.iloc[i], b.iloc[i]) for i in bad]
    return out


def _plain(value):
    """A numpy scalar as the Python value it holds (for readable failure lines)."""
    return value.item() if hasattr(value, "item") else value


def check_figure_data(regenerated, committed):
    """(number failed, report lines) of every CSV of the folder `committed` against the
    regenerated one of the same name: the same columns and rows, every number equal
    within round-off, every text equal."""
    lines, failed = [], 0
    paths = sorted(p for p in Path(committed).glob("*.csv") if p.name != COMPARISON)
    for path in paths:
        new_path = Path(regenerated) / path.name
        if not new_path.exists():
            failed += 1
            lines.append(f"FAIL figure data {path.name}: not regenerated")
            continue
        new, old = pd.read_csv(new_path), pd.read_csv(path)
        if list(new.columns) != list(old.columns) or len(new) != len(old):
            failed += 1
            lines.append(f"FAIL figure data {path.name}: {len(new)} rows of "
                         f"{list(new.columns)}, committed {len(old)} rows of "
                         f"{list(old.columns)}")
            continue
        cells = _differing_cells(new, old)
        if cells:
            failed += 1
            shown = "; ".join(f"row {i} {c} {_plain(a)!r}, committed {_plain(b)!r}"
                              for i, c, a, b in cells[:5])
            lines.append(f"FAIL figure data {path.name}: {len(cells)} cells differ: {shown}")
    lines.append(f"{'ok  ' if not failed else 'FAIL'} figure data: {len(paths) - failed} of "
                 f"{len(paths)} tables of {regenerated} as committed in {committed} (numbers "
                 f"within {ROUND_OFF_REL:g} relative)")
    return failed, lines


def run_checks(expectation_files, results):
    """All expectations of all files: (number failed, report lines)."""
    lines, failed = [], 0
    tables = Results(results)
    for path in expectation_files:
        for e in load_expectations(path):
            ok, message = check_one(e, tables)
            failed += not ok
            lines.append(message)
    return failed, lines


def main(argv=None):
    ap = argparse.ArgumentParser(description="Check figure data against expectations.")
    ap.add_argument("--results", default="results", help="folder the CSV paths start in")
    ap.add_argument("--report", help="also write the report to this file")
    ap.add_argument("expected", nargs="*", help="expectation YAML files")
    ap.add_argument("--committed", help="the committed figure data of this configuration: "
                    f"a folder of CSVs ({COMPARISON} and figure data) held against those "
                    "of the same name in RESULTS/figures")
    args = ap.parse_args(argv)
    try:
        failed, lines = run_checks(args.expected, args.results)
    except ExpectationError as err:
        print(f"check: error: {err}", file=sys.stderr)
        return 2
    total = len(lines)
    summary = f"check: {total - failed} of {total} expectations met, {failed} failed"
    if args.committed:
        figures = Path(args.results) / "figures"
        bad, more = check_comparison(figures / COMPARISON, Path(args.committed) / COMPARISON)
        lines += more
        failed += bad
        summary += f"; the paper comparison {'differs' if bad else 'is'} as committed"
        bad, more = check_figure_data(figures, args.committed)
        lines += more
        failed += bad
        summary += f"; the figure data {'differ' if bad else 'are'} as committed"
    text = "\n".join(lines + [summary]) + "\n"
    if args.report:
        Path(args.report).parent.mkdir(parents=True, exist_ok=True)
        Path(args.report).write_text(text, encoding="utf-8")
    print(text, end="", file=sys.stderr if failed else sys.stdout)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

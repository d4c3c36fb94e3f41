"""Compare figure data (CSV) with expected values and tolerances (config/expected/*.yaml).

An expectations file is YAML:

    expectations:
      - id: table1-mu-sp                 # unique name, shown in the report
        file: figures/table1.csv         # CSV, relative to the results folder
        where: {N_E: 5120}               # selects exactly one row (all fields must match)
        column: mu_sp                    # the value to check
        value: 0.81762                   # expected value, with rel_tol and/or abs_tol,
        rel_tol: 0.05                    #   or min/max bounds instead of value
        source: paper                    # analytic | paper | reference-run
        provenance: "Table 1, N_E = 5120 average (Ca 0.2, phi 0.3, M 100)"
        se_column: mu_sp_se              # optional: the standard error of the checked value
        value_se: 0.0                    # optional: the standard error of `value`

Every expectation must state where its value comes from (`source` and `provenance`);
a value copied from the same run it checks is not an expectation.

Standard errors: where the checked value is a time average (its row has a standard-error
column, analysis.statistics) or the expected value comes from a run with a known standard
error, `se_column` and `value_se` give them. The difference of two independent averages
then has the standard error se = sqrt(se_column^2 + value_se^2), and the value passes
within max(tolerance, k se) (analysis.verdict, the paper comparison's rule too): the
tolerance (rel_tol/abs_tol) stays the bound where it is the wider (it budgets the systematic differences, mesh and box, and in the suspension
expectations already the statistical spread: adding k se on top would count the
statistics twice), and k se takes over where the run is noisier than the tolerance
assumed, so a check does not fail on noise alone. k is the file's top-level `k`
(K_STANDARD_ERRORS = 3 when absent). Usage:
    python -m analysis.check --results results --report R.md config/expected/a.yaml ...
Exit status 1 if any expectation fails, with one readable line per failure.
"""

import argparse
import math
import sys
from pathlib import Path

import pandas as pd

from analysis.tables import read_yaml_list, select
from analysis.verdict import Missing, Results, at_least, at_most, band, within

SOURCES = ("analytic", "paper", "reference-run")
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
                                   f"got '{e['source']}'")
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
    ap.add_argument("expected", nargs="+", help="expectation YAML files")
    args = ap.parse_args(argv)
    try:
        failed, lines = run_checks(args.expected, args.results)
    except ExpectationError as err:
        print(f"check: error: {err}", file=sys.stderr)
        return 2
    total = len(lines)
    summary = f"check: {total - failed} of {total} expectations met, {failed} failed"
    text = "\n".join(lines + [summary]) + "\n"
    if args.report:
        Path(args.report).parent.mkdir(parents=True, exist_ok=True)
        Path(args.report).write_text(text, encoding="utf-8")
    print(text, end="", file=sys.stderr if failed else sys.stdout)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

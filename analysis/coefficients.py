"""The coefficients of section 4.2 per Ca, as one table that the figures and the paper
comparison both read (results/grid/fits.csv).

For each Ca with a dilute run in the grid table: a1, a2 of mu_sp(phi) and b1, b2 of N1(phi)
(eq. 4.6), each with its standard error, and the fitting range phi_max. The first
coefficient is the dilute-limit value, the second the least-squares fit of
(y - c1 phi) = c2 phi^2 over 0 < phi <= phi_max (analysis.fits.second_coefficient); c2 is
linear in c1 and the fitted values, so its error follows from theirs
(analysis.statistics.propagated_standard_error). A Ca with no phi in the range has c2 NaN.

Usage: python -m analysis.coefficients --phi-max 0.10 --out results/grid/fits.csv
       results/grid/table.csv
"""

import argparse
import math
import sys

import numpy as np
import pandas as pd

from analysis import fits
from analysis.statistics import propagated_standard_error
from analysis.tables import read_table, with_data, write_table

NAMES = {"mu_sp": ("a1", "a2"), "N1": ("b1", "b2")}  # eq. 4.6 and its N1 analogue
COLUMNS = ["ca", "phi_max"] + [c + s for pair in NAMES.values() for c in pair
                               for s in ("", "_se")]


def split_grid(table):
    """The runs of a grid table that hold averages: the dilute rows by Ca, and the
    suspension rows by Ca sorted by phi."""
    runs = with_data(table)
    dilute = {row["ca"]: row for _, row in runs[runs["intrinsic"] != 0].iterrows()}
    susp = {ca: group.sort_values("phi", kind="stable")
            for ca, group in runs[runs["intrinsic"] == 0].groupby("ca")}
    return dilute, susp


def _second(phi, values, first, phi_max):
    try:
        return fits.second_coefficient(phi, values, first, phi_max)
    except ValueError:  # no phi in the fitting range
        return math.nan


def _pair(dilute_row, rows, key, phi_max):
    """(c1, c1_se, c2, c2_se) of one Ca for `key`."""
    c1, c1_se = float(dilute_row[key]), float(dilute_row[key + "_se"])
    phi = rows["phi"].to_numpy(dtype=float)
    c2 = _second(phi, rows[key], c1, phi_max)
    if math.isnan(c2):
        return c1, c1_se, c2, math.nan
    c2_se = propagated_standard_error(
        lambda v: fits.second_coefficient(phi, v[1:], v[0], phi_max),
        np.concatenate([[c1], rows[key]]), np.concatenate([[c1_se], rows[key + "_se"]]))
    return c1, c1_se, c2, float(c2_se)


def coefficient_table(table, phi_max=fits.FIT_PHI_MAX):
    """One row per Ca that has a dilute run and suspension runs (COLUMNS)."""
    dilute, susp = split_grid(table)
    out = []
    for ca, rows in sorted(susp.items()):
        if ca not in dilute:
            continue
        row = {"ca": ca, "phi_max": phi_max}
        for key, (n1, n2) in NAMES.items():
            row[n1], row[n1 + "_se"], row[n2], row[n2 + "_se"] = _pair(dilute[ca], rows, key,
                                                                      phi_max)
        out.append(row)
    return pd.DataFrame(out, columns=COLUMNS)


def read_coefficients(path, key):
    """From a coefficient table: {ca: (c1, c2)}, {ca: (c1_se, c2_se)} of `key` ("mu_sp"
    or "N1"), and the fitting range."""
    table = read_table(path)
    n1, n2 = NAMES[key]
    coef = {r["ca"]: (r[n1], r[n2]) for _, r in table.iterrows()}
    errors = {r["ca"]: (r[n1 + "_se"], r[n2 + "_se"]) for _, r in table.iterrows()}
    phi_max = float(table["phi_max"].iloc[0]) if len(table) else fits.FIT_PHI_MAX
    return coef, errors, phi_max


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--phi-max", type=float, default=fits.FIT_PHI_MAX,
                    help="fitting range 0 < phi <= PHI_MAX of a2, b2 (paper: 0.10)")
    ap.add_argument("--out", required=True, help="the coefficient table (CSV)")
    ap.add_argument("grid", help="the grid study's table (results/grid/table.csv)")
    args = ap.parse_args(argv)
    if not args.phi_max > 0:
        print(f"coefficients: error: --phi-max must be > 0, got {args.phi_max}",
              file=sys.stderr)
        return 2
    write_table(args.out, coefficient_table(read_table(args.grid), args.phi_max), COLUMNS)
    return 0


if __name__ == "__main__":
    sys.exit(main())

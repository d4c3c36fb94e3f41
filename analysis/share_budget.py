"""Where the standard error of each O(phi^3) share comes from: the share
1 - (c1 phi + c2 phi^2) / y at one phi (the abstract's "only 8 %" reads mu_sp at phi 0.4)
depends on three independent averages, y at that phi, c2 (fitted over the low-phi runs)
and c1 (the dilute run), and its first-order error splits into theirs
(docs/suspensions.md, "The O(phi^3) shares' standard errors").

    python3 -m analysis.share_budget results/grid [--phi 0.4] [--key mu_sp]

Reads the grid's table.csv (the value at phi, its standard error) and fits.csv (c1, c2
and their standard errors: a1, a2 for mu_sp, b1, b2 for N1) and prints one row per Ca.
"""

import argparse
import functools
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.statistics import propagated_standard_error

COEFFICIENTS = {"mu_sp": ("a1", "a2"), "N1": ("b1", "b2")}


def higher_share(x, phi):
    """1 - (c1 phi + c2 phi^2) / y for x = (y, c1, c2)."""
    y, c1, c2 = x
    return 1.0 - (c1 * phi + c2 * phi**2) / y


def budget(table, fits, phi, key="mu_sp"):
    """One row per Ca: the share, its standard error from each input alone and in all."""
    c1, c2 = COEFFICIENTS[key]
    share = functools.partial(higher_share, phi=phi)
    rows = []
    for _, fit in fits.iterrows():
        point = table[(table.ca == fit.ca) & np.isclose(table.phi, phi)]
        if point.empty:
            continue
        y = point.iloc[0]
        x = np.array([y[key], fit[c1], fit[c2]])
        se = np.array([y[key + "_se"], fit[c1 + "_se"], fit[c2 + "_se"]])
        alone = [propagated_standard_error(share, x, np.where(np.arange(3) == j, se, 0.0))
                 for j in range(3)]
        rows.append({"ca": fit.ca, "phi": phi, "share": share(x),
                     f"se_from_{key}": alone[0], f"se_from_{c1}": alone[1],
                     f"se_from_{c2}": alone[2],
                     "se": propagated_standard_error(share, x, se), "t_end": y.t_end})
    return pd.DataFrame(rows)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("grid", type=Path, help="the grid's results folder (results/grid)")
    ap.add_argument("--phi", type=float, default=0.4)
    ap.add_argument("--key", choices=sorted(COEFFICIENTS), default="mu_sp")
    args = ap.parse_args(argv)
    table = pd.read_csv(args.grid / "table.csv")
    fits = pd.read_csv(args.grid / "fits.csv")
    print(budget(table, fits, args.phi, args.key).to_string(index=False,
                                                            float_format="%.4g"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

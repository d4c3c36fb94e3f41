"""Where the standard error of each O(phi^3) share comes from: the share
1 - (c1 phi + c2 phi^2) / y at one phi (the abstract's "only 8 %" reads mu_sp at phi 0.4)
depends on three independent averages, y at that phi, c2 (fitted over the low-phi runs)
and c1 (the dilute run), and its first-order error splits into theirs
(docs/suspensions.md, "The O(phi^3) shares' standard errors").

    python3 -m analysis.share_budget results/grid [--phi 0.4] [--key mu_sp]
        [--target SE [--eblimit results/eblimit/table.csv]]

Reads the grid's table.csv (the value at phi, its standard error) and fits.csv (c1, c2
and their standard errors: a1, a2 for mu_sp, b1, b2 for N1) and prints one row per Ca.

With --target, the plan to reach it: per Ca, the t_end to which the runs the share reads
(those fitting c2, 0 < phi <= phi_max, and the one at phi) must all go for its standard
error to be SE, if each run's statistical error falls as the square root of its window
[t_start, t_end]. At a point extrapolated to eb -> 0 the extrapolation's model part
(`<key>_model` of the eblimit table, analysis.bending_limit) does not fall with the window:
it sets a floor, below which no run length brings the share ("floor"); the two runs of
such a point each fall from their own window (eblimit.t_end_at may lengthen one).
"""

import argparse
import functools
import sys
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from analysis import membrane
from analysis.coefficients import coefficient_table
from analysis.fits import FIT_PHI_MAX
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


def model_parts(eblimit, key="mu_sp"):
    """{(ca, phi): the extrapolation's model part of `key`} from an eblimit table
    (analysis.bending_limit); empty for None."""
    if eblimit is None:
        return {}
    return {(r.ca, round(r.phi, 9)): float(r[key + "_model"])
            for _, r in eblimit.iterrows()}


def pair_runs(eblimit, key="mu_sp"):
    """{(ca, phi): [(weight, standard error, t_end) of each run]} of the points of an
    eblimit table extrapolated through two moduli: the weight of each run in the line's
    value at eb = 0, the grid's run's statistical error (`<key>_eb_se`) and the other's,
    what the limit's statistical error (the model part taken out) leaves of it. Their
    windows may differ (eblimit.t_end_at), so lengthened() takes each run on its own;
    points of three moduli are left out (their rows scale as one run)."""
    out = {}
    for _, r in (eblimit.iterrows() if eblimit is not None else []):
        eb = [float(x) for x in str(r.moduli).split()]
        if len(eb) != 2 or not np.isfinite(r[key]):
            continue
        t_end = [float(x) for x in str(r.t_end).split()]
        weight = [eb[1] / (eb[1] - eb[0]), -eb[0] / (eb[1] - eb[0])]
        grid = eb.index(membrane.parse(r.membrane, "grid.membranes")["eb"])
        stat2 = max(r[key + "_se"] ** 2 - r[key + "_model"] ** 2, 0.0)
        se = [0.0, 0.0]
        se[grid] = r[key + "_eb_se"]
        se[1 - grid] = np.sqrt(max(stat2 - (weight[grid] * se[grid]) ** 2, 0.0)) \
            / abs(weight[1 - grid])
        out[(r.ca, round(r.phi, 9))] = list(zip(weight, se, t_end))
    return out


def share_rows(table, ca, phi, phi_max=FIT_PHI_MAX):
    """The index of the suspension rows of `ca` that the share at phi reads: those that fit
    c2 (0 < phi <= phi_max) and the one at phi."""
    rows = table[np.isclose(table.ca, ca) & (table.phi > 0)]
    keep = (rows.phi <= phi_max + 1e-12) | np.isclose(rows.phi, phi)
    return rows.index[keep]


def lengthened(table, ca, phi, t_end, model, key="mu_sp", phi_max=FIT_PHI_MAX,
               runs=None):
    """The grid table with each run the share at (ca, phi) reads taken to t_end (none
    shortened): its statistical standard error (the model part taken out in quadrature)
    times sqrt(window now / window at t_end); t_end = inf leaves the model parts alone.
    A point of `runs` (pair_runs()) takes each of its runs so, on its own window."""
    out = table.copy()
    for i in share_rows(table, ca, phi, phi_max):
        row = out.loc[i]
        if not t_end > row.t_end:
            continue
        at = (row.ca, round(row.phi, 9))
        fixed = model.get(at, 0.0)
        parts = (runs or {}).get(at) or [
            (1.0, np.sqrt(max(row[key + "_se"] ** 2 - fixed**2, 0.0)), row.t_end)]
        var = 0.0
        for weight, se, t in parts:
            ratio = 1.0 if not t_end > t else (
                0.0 if np.isinf(t_end) else (t - row.t_start) / (t_end - row.t_start))
            var += (weight * se) ** 2 * ratio
        out.loc[i, key + "_se"] = np.hypot(np.sqrt(var), fixed)
        out.loc[i, "t_end"] = t_end
    return out


def share_se(table, ca, phi, key="mu_sp", phi_max=FIT_PHI_MAX):
    """The share's standard error at (ca, phi), its coefficients fitted from `table`."""
    rows = budget(table, coefficient_table(table, phi_max), phi, key)
    return float(rows[np.isclose(rows.ca, ca)].se.iloc[0])


def plan(table, phi, target, model, key="mu_sp", phi_max=FIT_PHI_MAX, runs=None):
    """Per Ca: the share's standard error now, its floor (every run the share reads
    unbounded), the t_end that brings it to `target` (runs already longer kept as they
    are; the shortest run's t_end where it is met, inf where the floor is above it) and
    the runs among them that stopped before their t_end (they would need a membrane or a
    repulsion that carries them first)."""
    out = []
    for ca in sorted(set(budget(table, coefficient_table(table, phi_max), phi, key).ca)):
        rows = table.loc[share_rows(table, ca, phi, phi_max)]
        start = float(rows.t_end.min())  # lengthened() leaves the table as it is

        def se_at(t):
            return share_se(lengthened(table, ca, phi, t, model, key, phi_max, runs), ca,
                            phi, key, phi_max)
        now, floor = se_at(start), se_at(np.inf)
        if now <= target:
            t_needed = start
        elif floor >= target:
            t_needed = np.inf
        else:
            high = 2.0 * start
            while se_at(high) > target:
                high *= 2.0
            t_needed = brentq(lambda t: se_at(t) - target, start, high, xtol=0.1)
        stopped = rows[rows.ended != "t_end"]
        out.append({"ca": ca, "se": now, "floor": floor, "t_end_needed": t_needed,
                    "t_end_now": " ".join(f"{t:.4g}" for t in rows.t_end),
                    "stopped": " ".join(f"phi {r.phi:g} ({r.ended} at {r.t_end:.3g})"
                                        for _, r in stopped.iterrows())})
    return pd.DataFrame(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("grid", type=Path, help="the grid's results folder (results/grid)")
    ap.add_argument("--phi", type=float, default=0.4)
    ap.add_argument("--key", choices=sorted(COEFFICIENTS), default="mu_sp")
    ap.add_argument("--target", type=float, help="the share's standard error to plan for")
    ap.add_argument("--eblimit", type=Path,
                    help="the eblimit table (default: results/eblimit/table.csv beside the "
                         "grid's folder, where it exists)")
    args = ap.parse_args(argv)
    table = pd.read_csv(args.grid / "table.csv")
    if args.target is None:
        fits = pd.read_csv(args.grid / "fits.csv")
        rows = budget(table, fits, args.phi, args.key)
    else:
        if not args.target > 0:
            ap.error(f"--target must be > 0, got {args.target}")
        eblimit = args.eblimit or args.grid.parent / "eblimit" / "table.csv"
        limits = pd.read_csv(eblimit) if eblimit.exists() else None
        rows = plan(table, args.phi, args.target, model_parts(limits, args.key), args.key,
                    runs=pair_runs(limits, args.key))
    print(rows.to_string(index=False, float_format="%.4g"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

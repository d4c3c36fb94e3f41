"""The rule by which the figure-data check (analysis.check) sets a number of ours against
an expected one (an analytic limit, a reference run), and the tables that the check and
the paper comparison (analysis.paper_comparison, with its own rule for the paper's
claims) read.

A value agrees with the expected one when their difference lies within the band
max(tolerance, k se), with se = sqrt(se_ours^2 + se_expected^2) the standard error of the
difference of two independent estimates: the tolerance budgets what the standard errors do
not hold (systematic differences of mesh and box between a run and its reference), k se
the statistics. A bound (at most, at least) holds when ours lies on its side within k of
its own standard errors. Each expectation file says its k (3: a dozen checks at once
should not fail on noise, analysis.check).
"""

from pathlib import Path

from analysis.tables import read_table


def band(tolerance=0.0, se=0.0, k=0.0):
    """The half-width of the agreement band: max(tolerance, k se)."""
    return max(tolerance, k * se)


def within(ours, expected, tolerance=0.0, se=0.0, k=0.0):
    """Whether |ours - expected| <= max(tolerance, k se)."""
    return abs(ours - expected) <= band(tolerance, se, k)


def at_most(ours, bound, se=0.0, k=0.0):
    """Whether ours - k se <= bound (ours is not shown to exceed the bound)."""
    return ours - k * se <= bound


def at_least(ours, bound, se=0.0, k=0.0):
    """Whether ours + k se >= bound."""
    return ours + k * se >= bound


class Missing(Exception):
    """What a results folder lacks for a number (a file, a row, a column)."""


class Results:
    """The CSV tables of one results folder, read once each."""

    def __init__(self, folder):
        self.folder = Path(folder)
        self._tables = {}

    def table(self, name):
        if name not in self._tables:
            path = self.folder / name
            if not path.exists():
                raise Missing(f"no {name}")
            self._tables[name] = read_table(path)
        return self._tables[name]

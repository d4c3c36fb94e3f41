"""Analysis of capsim runs: reading run directories, time averages, figure data.

Figures and the workflow read runs only through this package, never solver internals.
"""

from analysis.read_run import read_summary, read_timeseries, time_average

__all__ = ["read_summary", "read_timeseries", "time_average"]

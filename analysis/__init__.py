"""Analysis of capsim runs: reading run directories, time and ensemble averages, the
polynomial fits and Krieger-Dougherty relation of section 4.2, the stresslet
decomposition of section 4.3, figure data tables and the check against expected values.

Figures and the workflow read runs only through this package, never solver internals.
Plain Python on numpy/scipy/pandas/h5py (and PyYAML for the expectation files).
"""

from analysis.read_run import read_summary, read_timeseries, time_average

__all__ = ["read_summary", "read_timeseries", "time_average"]

"""Standard errors of time averages of correlated samples.

Successive samples of a run are correlated over a strain of order one, so the naive
std/sqrt(n) underestimates the error of a time average. The error used throughout is
s sqrt(2 tau_int / n), with tau_int the integrated autocorrelation time in samples
(Sokal's automatic window, c = 5). It was chosen over block averaging with blocks of a
few tau_int: on AR(1) series with tau_int 4.5 samples and 200 samples (a window [10, 20] sampled every
0.05 holds 200) it is 9 % low on average
with a 24 % scatter, where blocks of 2 tau_int are 27 % low and blocks of 10 tau_int
scatter by 41 % (tests/python/test_statistics.py checks the first).

For a suspension the series is the capsule mean at each sample (the capsules of one box
are correlated with each other too, so they are not independent samples).
"""

import math

import numpy as np

SOKAL_WINDOW = 5.0  # window W: the smallest with W >= c tau_int(W) (Sokal 1997, c = 5)


def integrated_autocorrelation_time(x):
    """tau_int of the 1-D series `x`, in samples: 1/2 + sum_{k=1}^{W} rho(k) with the
    automatic window W. 0.5 for uncorrelated samples; 0.5 for a constant series."""
    x = np.asarray(x, dtype=float)
    if x.size < 2:
        return 0.5
    dev = x - x.mean()
    # Imported here: the workflow imports this module at every start (through the
    # accuracy study's plan), and scipy.signal takes about 0.6 s to import.
    from scipy import signal
    acov = signal.correlate(dev, dev, mode="full", method="fft")[x.size - 1:]
    if acov[0] <= 0.0:
        return 0.5
    rho = acov / acov[0]
    tau = 0.5 + np.cumsum(rho[1:])
    window = np.arange(1, x.size)
    inside = window < SOKAL_WINDOW * tau
    # The first window that holds c tau; all of the series when none does.
    last = int(np.argmin(inside)) if not inside.all() else x.size - 2
    return float(max(tau[last], 0.5))


def mean_standard_error(x):
    """Standard error of the mean of the 1-D series `x`: s sqrt(2 tau_int / n).

    Returns (standard_error, tau_int). n / (2 tau_int) is the number of effectively
    independent samples; NaN for fewer than two samples.
    """
    x = np.asarray(x, dtype=float)
    if x.size < 2:
        return math.nan, 0.5
    tau = integrated_autocorrelation_time(x)
    return float(x.std(ddof=1) * math.sqrt(2.0 * tau / x.size)), tau


def standard_error(series, time, t_start, t_end):
    """Standard error of the time average over [t_start, t_end], per component.

    `series` has the sample index first, then optionally the capsule index, then any
    component axes (as analysis.read_run.time_average). The capsule axis is averaged
    first. Returns a float, or an array of the component shape.
    """
    series = np.asarray(series, dtype=float)
    window = (np.asarray(time) >= t_start) & (np.asarray(time) <= t_end)
    selected = series[window]
    if selected.ndim >= 2:
        selected = selected.mean(axis=1)
    flat = selected.reshape(selected.shape[0], -1)
    errors = np.array([mean_standard_error(flat[:, j])[0] for j in range(flat.shape[1])])
    return float(errors[0]) if selected.ndim == 1 else errors.reshape(selected.shape[1:])


def spread_standard_error(series, time, t_start, t_end):
    """Standard error of the population standard deviation over all (sample, capsule)
    values in [t_start, t_end] (sigma_D, sigma_theta_D of eq. 4.1), for a series of shape
    (n,) or (n, M).

    sigma^2 is itself a time average: that of v(t), the capsule mean at each sample of
    (x - <x>)^2, with <x> the mean over the window. Its standard error is that of any time
    average (standard_error of v), and sigma = sqrt(sigma^2) carries it to first order
    divided by 2 sigma (the delta method). v is, up to a constant, the linearised series of
    <x^2> - <x>^2 in the capsule means of x and x^2; the estimated <x> enters only to
    second order (d sigma^2 / d<x> = 0 at the mean). The series v keeps the correlation
    of the capsules and of successive samples, as for the mean. The series of each
    sample's spread over capsules would not do: its mean leaves out how the capsule mean
    moves in time, which sigma includes. 0 for a constant series.
    """
    series = np.asarray(series, dtype=float)
    window = (np.asarray(time) >= t_start) & (np.asarray(time) <= t_end)
    squared = (series - series[window].mean()) ** 2
    sigma = math.sqrt(float(squared[window].mean()))
    if sigma == 0.0:
        return 0.0
    return standard_error(squared, time, t_start, t_end) / (2.0 * sigma)


def mean_of_runs_standard_error(errors):
    """Standard error of the mean of n independent runs' averages, from their standard
    errors: sqrt(sum se_i^2) / n. NaN if any is NaN (or none is given)."""
    errors = np.asarray(errors, dtype=float)
    if errors.size == 0:
        return math.nan
    return float(np.sqrt(np.sum(errors**2)) / errors.size)


def propagated_standard_error(func, values, errors):
    """Standard error of func(values) for independent estimates `values` with standard
    errors `errors`, to first order (the delta method): sqrt(sum_j (df/dx_j se_j)^2).

    Each term is the central difference (f(x + se_j e_j) - f(x - se_j e_j)) / 2, exact for
    a function linear in x_j. `func` maps a 1-D array to a number or an array; the result
    has its shape. An input with a NaN standard error makes the result NaN.
    """
    x = np.asarray(values, dtype=float)
    se = np.asarray(errors, dtype=float)
    variance = np.zeros_like(np.asarray(func(x), dtype=float))
    for j in np.flatnonzero(se != 0.0):  # NaN != 0 too: it propagates
        step = np.zeros_like(x)
        step[j] = se[j]
        half = (np.asarray(func(x + step), dtype=float)
                - np.asarray(func(x - step), dtype=float)) / 2.0
        variance = variance + half**2
    out = np.sqrt(variance)
    return float(out) if out.ndim == 0 else out

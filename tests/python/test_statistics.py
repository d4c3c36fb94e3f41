"""The standard error of a time average of correlated samples (analysis.statistics),
against AR(1) series whose autocorrelation time is known in closed form."""

import numpy as np
import pytest

from analysis.statistics import (integrated_autocorrelation_time, mean_of_runs_standard_error,
                                 mean_standard_error, propagated_standard_error,
                                 spread_standard_error, standard_error)


def ar1(rng, phi, samples, series=1):
    """`series` stationary AR(1) series x_i = phi x_{i-1} + e_i with unit noise; their
    tau_int is (1 + phi) / (2 (1 - phi)) samples."""
    noise = rng.standard_normal((series, samples))
    x = np.empty_like(noise)
    x[:, 0] = noise[:, 0] / np.sqrt(1.0 - phi**2)
    for i in range(1, samples):
        x[:, i] = phi * x[:, i - 1] + noise[:, i]
    return x


def test_autocorrelation_time_of_a_long_series():
    # 2e5 samples: the estimate's own error is about sqrt(2 (2W + 1) / n) tau, 2 %.
    x = ar1(np.random.default_rng(1), 0.8, 200_000)[0]
    assert integrated_autocorrelation_time(x) == pytest.approx(4.5, rel=0.05)


def test_uncorrelated_and_constant_series():
    x = np.random.default_rng(2).standard_normal(20_000)
    assert integrated_autocorrelation_time(x) == pytest.approx(0.5, abs=0.05)
    assert integrated_autocorrelation_time(np.full(50, 3.0)) == 0.5
    assert mean_standard_error(np.full(50, 3.0))[0] == 0.0


def test_standard_error_matches_the_spread_of_means():
    # 1000 series of 200 samples (tau_int 4.5): the standard error must describe the
    # spread of their means. The estimator is biased low by the finite window (9 %
    # here); 15 % allows for that and the 2 % sampling error of the spread itself.
    xs = ar1(np.random.default_rng(3), 0.8, 200, series=1000)
    spread = xs.mean(axis=1).std()
    errors = np.array([mean_standard_error(x)[0] for x in xs])
    assert np.sqrt(np.mean(errors**2)) == pytest.approx(spread, rel=0.15)
    naive = xs.std(axis=1, ddof=1).mean() / np.sqrt(200)
    assert naive < 0.5 * spread  # what ignoring the correlation would report


def test_standard_error_of_a_run_series_averages_capsules_first():
    rng = np.random.default_rng(4)
    time = np.arange(400) * 0.05
    common = ar1(rng, 0.8, 400)[0]
    series = common[:, None] + 0.0 * rng.standard_normal((400, 3))  # 3 equal capsules
    window = time >= 10.0
    expected = mean_standard_error(common[window])[0]
    assert standard_error(series, time, 10.0, 20.0) == pytest.approx(expected, rel=1e-12)
    tensor = np.broadcast_to(series[:, :, None, None], (400, 3, 3, 3))
    assert standard_error(tensor, time, 10.0, 20.0).shape == (3, 3)


def test_spread_standard_error_of_uncorrelated_gaussian_samples():
    # n samples of M independent capsules, all values iid N(0, s^2): the population
    # standard deviation of the n M values has the standard error s / sqrt(2 n M) (large
    # n). With M copies of one capsule the values are not independent: s / sqrt(2 n).
    rng = np.random.default_rng(5)
    n, m, s = 20_000, 4, 2.0
    time = np.arange(n) * 0.05
    x = s * rng.standard_normal((n, m))
    assert spread_standard_error(x, time, 0.0, time[-1]) == pytest.approx(
        s / np.sqrt(2 * n * m), rel=0.05)
    same = np.repeat(x[:, :1], m, axis=1)
    assert spread_standard_error(same, time, 0.0, time[-1]) == pytest.approx(
        s / np.sqrt(2 * n), rel=0.05)
    assert spread_standard_error(np.full((50, 3), 7.0), time[:50], 0.0, 10.0) == 0.0


def test_spread_standard_error_matches_the_spread_of_standard_deviations():
    # 1000 runs of 4 independent AR(1) capsules (tau_int 4.5), 200 samples: the standard
    # error must describe how the standard deviation over (sample, capsule) values
    # scatters from run to run (15 %: as for the mean, above; the naive error, without
    # the correlation, is half of it).
    rng = np.random.default_rng(6)
    time = np.arange(200) * 0.05
    runs = ar1(rng, 0.8, 200, series=4000).reshape(1000, 4, 200).transpose(0, 2, 1)
    spread = runs.reshape(1000, -1).std(axis=1).std()
    errors = np.array([spread_standard_error(x, time, 0.0, 10.0) for x in runs])
    assert np.sqrt(np.mean(errors**2)) == pytest.approx(spread, rel=0.15)


def test_mean_of_independent_runs():
    # Three runs: sqrt(0.03^2 + 0.04^2 + 0.12^2) / 3 = 0.13 / 3.
    assert mean_of_runs_standard_error([0.03, 0.04, 0.12]) == pytest.approx(0.13 / 3)
    assert np.isnan(mean_of_runs_standard_error([0.01, np.nan]))


def test_propagation_of_a_ratio_and_a_linear_map():
    # x / y: relative errors add in quadrature (to first order).
    se = propagated_standard_error(lambda v: v[0] / v[1], [2.0, 4.0], [0.02, 0.01])
    assert se == pytest.approx(0.5 * np.hypot(0.01, 0.0025), rel=1e-4)
    # A linear map A x: sqrt(sum_j (A_ij se_j)^2) exactly, per output.
    a = np.array([[1.0, 2.0], [0.0, -3.0]])
    got = propagated_standard_error(lambda v: a @ v, [1.0, 1.0], [0.1, 0.2])
    assert got == pytest.approx([np.hypot(0.1, 0.4), 0.6])
    assert np.isnan(propagated_standard_error(lambda v: v.sum(), [1.0, 1.0], [0.1, np.nan]))
    assert propagated_standard_error(lambda v: v.sum(), [1.0, 1.0], [0.0, 0.0]) == 0.0

"""Time and ensemble averages of one run and of several seeds (paper eqs. 4.1 and A3).

Samples are equally spaced in time, so the time integral of eq. A3 is the sample mean.
Defaults follow the paper: averages from gammadot*t_s = 10 to the end of the run.
"""

import numpy as np

from analysis.read_run import time_average
from analysis.statistics import spread_standard_error, standard_error
from analysis.stresslet import decomposition_gradients

T_START = 10.0  # paper section 4.1: the average starts after gammadot*t = 10


def window_end(time, t_end=None):
    """The end of the averaging window: t_end, or the last sample time when None."""
    return float(np.max(time)) if t_end is None else float(t_end)


def run_averages(ts, t_start=T_START, t_end=None):
    """Averages of one run's time series `ts` (as read_timeseries returns it).

    Means and standard deviations are over all (sample, capsule) pairs with
    t_start <= t <= t_end (eq. 4.1); the standard errors (_se) are those of the time
    average of the capsule mean (analysis.statistics), those of the standard deviations
    (D_std_se, theta_D_std_se_deg) by spread_standard_error. Returns a dict: D, D_std,
    D_se, D_std_se, theta_D_deg, theta_D_std_deg, theta_D_se_deg, theta_D_std_se_deg,
    principal_diff (<S1 - S2>),
    theta_S_deg, stresslet (3x3 mean, Gs a^2), stresslet_se (3x3), normal_differences_se
    (of S_xx - S_yy and S_yy - S_zz), principal_diff_se, theta_S_se_deg,
    decomposition_se (dict: the standard errors of the right-hand sides of eqs. 4.14, 4.15
    and of sin, cos 2<theta_S>, analysis.stresslet.decomposition_gradients), count (sample
    values), t_start, t_end, capsules.
    """
    time = ts["time"]
    t_end = window_end(time, t_end)
    out = {"t_start": float(t_start), "t_end": t_end, "capsules": int(ts["D"].shape[1])}
    mean, std, count = time_average(ts["D"], time, t_start, t_end)
    out["D"], out["D_std"] = mean, std
    mean, std, _ = time_average(ts["theta_D_deg"], time, t_start, t_end)
    out["theta_D_deg"], out["theta_D_std_deg"] = mean, std
    out["principal_diff"] = time_average(ts["principal_diff"], time, t_start, t_end)[0]
    out["theta_S_deg"] = time_average(ts["theta_S_deg"], time, t_start, t_end)[0]
    out["stresslet"] = time_average(ts["stresslet"], time, t_start, t_end)[0]
    out["count"] = count
    out["D_se"] = standard_error(ts["D"], time, t_start, t_end)
    out["theta_D_se_deg"] = standard_error(ts["theta_D_deg"], time, t_start, t_end)
    out["D_std_se"] = spread_standard_error(ts["D"], time, t_start, t_end)
    out["theta_D_std_se_deg"] = spread_standard_error(ts["theta_D_deg"], time, t_start, t_end)
    s = np.asarray(ts["stresslet"], dtype=float)
    out["stresslet_se"] = standard_error(s, time, t_start, t_end)
    differences = np.stack([s[..., 0, 0] - s[..., 1, 1], s[..., 1, 1] - s[..., 2, 2]], -1)
    out["normal_differences_se"] = standard_error(differences, time, t_start, t_end)
    out["principal_diff_se"] = standard_error(ts["principal_diff"], time, t_start, t_end)
    out["theta_S_se_deg"] = standard_error(ts["theta_S_deg"], time, t_start, t_end)
    gradients = decomposition_gradients(out["principal_diff"], out["theta_S_deg"])
    out["decomposition_se"] = {
        name: standard_error(a * np.asarray(ts["principal_diff"], dtype=float)
                             + b * np.asarray(ts["theta_S_deg"], dtype=float),
                             time, t_start, t_end)
        for name, (a, b) in gradients.items()}
    return out


def running_average(series, time, t_start, t_ends):
    """<f>(t_e) of eq. A3 for every end time in `t_ends` (figure 11).

    `series` is (n,) or (n, M) (averaged over capsules too). Returns an array of
    len(t_ends); NaN where no sample lies in [t_start, t_e].
    """
    out = np.full(len(t_ends), np.nan)
    for i, t_e in enumerate(t_ends):
        if np.any((time >= t_start) & (time <= t_e)):
            out[i] = time_average(series, time, t_start, t_e)[0]
    return out


def running_standard_error(series, time, t_start, t_ends):
    """The standard error (analysis.statistics) of <f>(t_e) for every end time in
    `t_ends`, as running_average; NaN where fewer than two samples lie in [t_start, t_e].
    Near t_s the window holds few correlation times and the estimate is rough."""
    out = np.full(len(t_ends), np.nan)
    for i, t_e in enumerate(t_ends):
        if np.count_nonzero((time >= t_start) & (time <= t_e)) >= 2:
            out[i] = standard_error(series, time, t_start, t_e)
    return out


def ensemble(values, ddof=0):
    """Mean and standard deviation over cases (seeds, initial positions): axis 0.

    ddof = 0 gives the population standard deviation of the cases, as the paper's
    "standard deviation of three cases" (appendix A.2, A.3); ddof = 1 the sample one.
    With a single case the standard deviation is 0.
    """
    values = np.asarray(values, dtype=float)
    mean = values.mean(axis=0)
    std = values.std(axis=0, ddof=ddof) if values.shape[0] > ddof else np.zeros_like(mean)
    return mean, std

"""Read one capsim run directory: summary.json and timeseries.h5.

Layout of timeseries.h5 (one row per sample; M capsules; see solver/io/timeseries_file.hpp):

    /time                     (n,)         strain gammadot*t
    /step                     (n,)         int64 time-step index
    /capsule/D                (n, M)       Taylor parameter
    /capsule/theta_D_deg      (n, M)       orientation of the major axis, degrees
    /capsule/principal_diff   (n, M)       S1 - S2, in Gs a^2
    /capsule/theta_S_deg      (n, M)       orientation of S1, degrees
    /capsule/energy           (n, M)       membrane energy, in Gs a^2
    /capsule/volume_error     (n, M)       (V - V0) / V0 of the state
    /capsule/volume_drift     (n, M)       largest one-step (V - V0) / V0 before the constraint
    /capsule/stresslet        (n, M, 3, 3) in Gs a^2
    /capsule/centroid         (n, M, 3)

and, in files of later versions only (OPTIONAL_CAPSULE_DATASETS):

    /capsule/repelled_nodes       (n, M)   nodes within the repulsion range of others
    /capsule/compressed_elements  (n, M)   elements with T2 (eq. 2.10) below -1e-3 Gs
    /capsule/min_tension          (n, M)   the smallest T2 of any element, in Gs

Conventions (axes, units, definitions) are those of docs/conventions.md.
"""

import json
from pathlib import Path

import h5py
import numpy as np

SUMMARY_FILE = "summary.json"
TIMESERIES_FILE = "timeseries.h5"

# Per-capsule datasets: key in the returned dict -> shape after the leading (n, M).
CAPSULE_DATASETS = {
    "D": (),
    "theta_D_deg": (),
    "principal_diff": (),
    "theta_S_deg": (),
    "energy": (),
    "volume_error": (),
    "volume_drift": (),
    "stresslet": (3, 3),
    "centroid": (3,),
}

# Per-capsule datasets that older files lack: read under the same keys when present.
OPTIONAL_CAPSULE_DATASETS = {
    "repelled_nodes": (),
    "compressed_elements": (),
    "min_tension": (),
}


def read_summary(run_dir):
    """Return the run's summary.json as a dict."""
    path = Path(run_dir) / SUMMARY_FILE
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def read_timeseries(run_dir):
    """Return the run's timeseries.h5 as a dict of numpy arrays.

    Keys: "time" (n,), "step" (n,) int64, and the per-capsule series named by their dataset
    ("D", "theta_D_deg", ..., "stresslet" (n, M, 3, 3), "centroid" (n, M, 3)); those of
    OPTIONAL_CAPSULE_DATASETS ("repelled_nodes", "compressed_elements", "min_tension")
    only where the file has them (older files do not). Any other dataset in the file is
    included under its path without the leading slash (e.g. "global/particle_stress").
    Raises ValueError if a dataset is missing or its shape does not match (n) and (n, M).
    """
    path = Path(run_dir) / TIMESERIES_FILE
    out = {}
    with h5py.File(path, "r") as f:
        for name in ["time", "step"] + [f"capsule/{k}" for k in CAPSULE_DATASETS]:
            if name not in f:
                raise ValueError(f"{path}: dataset /{name} is missing")
        time = f["time"][()]
        step = f["step"][()].astype(np.int64)
        n = time.shape[0] if time.ndim == 1 else -1
        if n < 0 or step.shape != (n,):
            raise ValueError(f"{path}: /time {time.shape} and /step {step.shape} "
                             "must both have shape (n,)")
        out["time"] = time
        out["step"] = step
        d_shape = f["capsule/D"].shape
        if len(d_shape) != 2:
            raise ValueError(f"{path}: /capsule/D has shape {d_shape}, expected (n, M)")
        num_capsules = d_shape[1]
        columns = dict(CAPSULE_DATASETS)
        columns.update({key: tail for key, tail in OPTIONAL_CAPSULE_DATASETS.items()
                        if "capsule/" + key in f})
        for key, tail in columns.items():
            data = f["capsule/" + key][()]
            want = (n, num_capsules) + tail
            if data.shape != want:
                raise ValueError(f"{path}: /capsule/{key} has shape {data.shape}, "
                                 f"expected {want}")
            out[key] = data

        known = {"time", "step"} | {"capsule/" + k for k in columns}

        def add_extra(name, obj):
            if isinstance(obj, h5py.Dataset) and name not in known:
                out[name] = obj[()]

        f.visititems(add_extra)
    return out


def time_average(series, time, t_start, t_end, ddof=0):
    """Mean and standard deviation of `series` over the samples with t_start <= time <= t_end.

    `series` has the sample index first, then optionally the capsule index, then any
    component axes: shape (n,), (n, M), (n, M, 3) or (n, M, 3, 3). Mean and standard
    deviation are taken over all (sample, capsule) pairs together (paper eq. 4.1), per
    component. Returns (mean, std, count) with count the number of (sample, capsule)
    pairs; std uses `ddof` (0: the population standard deviation).
    Raises ValueError if no sample lies in the window.
    """
    series = np.asarray(series, dtype=float)
    time = np.asarray(time, dtype=float)
    if time.ndim != 1 or series.shape[:1] != time.shape:
        raise ValueError(f"series of shape {series.shape} does not match time of shape "
                         f"{time.shape}")
    window = (time >= t_start) & (time <= t_end)
    selected = series[window]
    if selected.ndim >= 2:  # merge the sample and capsule axes
        selected = selected.reshape((-1,) + selected.shape[2:])
    count = selected.shape[0]
    if count == 0:
        span = f"[{time.min()}, {time.max()}]" if time.size else "empty"
        raise ValueError(f"no samples with {t_start} <= time <= {t_end} (times: {span})")
    mean = selected.mean(axis=0)
    std = selected.std(axis=0, ddof=ddof)
    if mean.ndim == 0:
        mean, std = float(mean), float(std)
    return mean, std, count

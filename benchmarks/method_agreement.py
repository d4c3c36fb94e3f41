"""Do two Ewald methods give the same rheology? Runs one suspension case with each method
(same packing) and compares <D> and mu_sp over the averaging window with their
statistical errors (agreement: the difference within twice the combined standard error),
and the two trajectories sample by sample.

Usage: .venv/bin/python benchmarks/method_agreement.py [--capsules M] [--mesh-level N]
           [--ca CA] [--phi PHI] [--t-end T] [--t-start TS] [--methods spectral,direct]
           [--tolerance TOL[,TOL]] [--blocks B]
--tolerance takes one value for all methods or one per method (for example
`--methods direct,spectral --tolerance 1e-4,1e-6`: direct at 1e-4, spectral at its default).
Writes results/benchmarks/agreement_<case>.json and .md. A run folder that already holds
a finished run is reused and an unfinished one is resumed, so a long comparison (the
paper's Table 1 case with `direct` at 1e-4 takes about 1.6 hours on two cores) can be
run in pieces.

The statistical error of a window average is the standard error of B block averages of
the capsule-averaged series (B = 5 by default): neighbouring samples are correlated, the
blocks of 2 strain units or more much less so.
"""

import argparse
import json
import math
import pathlib
import subprocess

import numpy as np
import pandas as pd

from analysis.read_run import read_timeseries
from analysis.rheology import particle_stress
from analysis.tables import markdown_table
from pipeline.run_spec import RunSpec

ROOT = pathlib.Path(__file__).resolve().parent.parent

OUT = ROOT / "results" / "benchmarks"
CAPSIM = ROOT / "build" / "capsim"


def method_spec(a, case, method, tolerance):
    """The run of one method, in results/benchmarks/agreement_<case>_<method>."""
    return RunSpec(study="benchmarks", label=f"agreement_{case}_{method}", ca=a.ca,
                   level=a.mesh_level, t_end=a.t_end, t_avg_start=a.t_start, phi=a.phi,
                   M=a.capsules, seed=a.seed, snapshot_interval=0,
                   options=(("ewald.tolerance", tolerance), ("method", method)))


def run(spec):
    """Runs (or resumes, or reuses) capsim for one method; returns the folder."""
    folder = ROOT / spec.folder
    summary = folder / "summary.json"
    if summary.exists():
        s = json.loads(summary.read_text())
        if s.get("ended") != "t_end" or s["t_end"] >= spec.t_end:  # stopped early, or done
            return folder
    cmd, _ = spec.command(CAPSIM, threads=0, root=ROOT)  # 0: OpenMP's default, as capsim's
    print(" ".join(cmd[1:]), flush=True)
    subprocess.run(cmd, check=False)  # exit 3 (early stop) still leaves a summary
    return folder


def window_statistics(series, time, t_start, t_end, blocks):
    """Mean over the window and the standard error of `blocks` block means."""
    inside = (time >= t_start) & (time <= t_end)
    values = series[inside]
    parts = np.array_split(values, blocks)
    means = np.array([p.mean() for p in parts])
    return float(values.mean()), float(means.std(ddof=1) / math.sqrt(blocks))


def case_series(ts, a):
    """Capsule-averaged D and mu_sp (eq. 4.5, Sigma^p_xy / mu gammadot) per sample."""
    stress = particle_stress(ts["stresslet"].mean(axis=1), a.phi, a.ca)
    return {"D": ts["D"].mean(axis=1), "mu_sp": stress[:, 0, 1]}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--capsules", type=int, default=8)
    p.add_argument("--mesh-level", type=int, default=2)
    p.add_argument("--ca", type=float, default=0.2)
    p.add_argument("--phi", type=float, default=0.3)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--t-end", type=float, default=20.0)
    p.add_argument("--t-start", type=float, default=10.0)
    p.add_argument("--tolerance", default="1e-6",
                   help="Ewald tolerance, one for all methods or one per method")
    p.add_argument("--methods", default="spectral,direct")
    p.add_argument("--blocks", type=int, default=5)
    a = p.parse_args()
    case = f"M{a.capsules}_L{a.mesh_level}_Ca{a.ca:g}_phi{a.phi:g}_s{a.seed}"
    OUT.mkdir(parents=True, exist_ok=True)
    methods = a.methods.split(",")
    tolerances = [float(t) for t in a.tolerance.split(",")]
    if len(tolerances) == 1:
        tolerances *= len(methods)
    if len(tolerances) != len(methods):
        p.error("--tolerance: give one value, or one per method")
    series, rows, wall = {}, [], {}
    for method, tolerance in zip(methods, tolerances):
        folder = run(method_spec(a, case, method, tolerance))
        summary = json.loads((folder / "summary.json").read_text())
        ts = read_timeseries(folder)
        t_end = min(a.t_end, float(ts["time"].max()))
        series[method] = (ts["time"], case_series(ts, a), ts["D"])
        wall[method] = summary.get("wall_seconds")
        row = {"method": method, "tolerance": tolerance, "t_end": t_end,
               "ended": summary.get("ended"),
               "wall_seconds": wall[method]}
        for name, values in series[method][1].items():
            row[name], row[name + "_error"] = window_statistics(
                values, ts["time"], a.t_start, t_end, a.blocks)
        rows.append(row)
    first, second = rows[0], rows[1]
    compare = {}
    for name in ("D", "mu_sp"):
        diff = second[name] - first[name]
        error = math.hypot(first[name + "_error"], second[name + "_error"])
        compare[name] = {"difference": diff, "combined_error": error,
                         "within_two_errors": abs(diff) <= 2 * error}
    # The trajectories sample by sample: when do the two runs part?
    t0, _, d0 = series[methods[0]]
    t1, _, d1 = series[methods[1]]
    n = min(len(t0), len(t1))
    gap = np.abs(d0[:n] - d1[:n]).max(axis=1)
    parted = np.nonzero(gap > 1e-3)[0]
    compare["max_D_gap_to_t1"] = float(gap[t0[:n] <= 1.0].max())
    compare["t_D_gap_above_1e-3"] = float(t0[parted[0]]) if len(parted) else None
    result = {"case": case, "t_start": a.t_start, "blocks": a.blocks,
              "runs": rows, "comparison": compare}
    (OUT / f"agreement_{case}.json").write_text(json.dumps(result, indent=2) + "\n")
    columns = ["method", "tolerance", "t_end", "D", "D_error", "mu_sp", "mu_sp_error",
               "wall_seconds"]
    lines = [markdown_table(pd.DataFrame(rows)[columns],
                            {"tolerance": "g", "t_end": "g", "D": ".4f", "D_error": ".4f",
                             "mu_sp": ".4f", "mu_sp_error": ".4f", "wall_seconds": ".0f"},
                            ["method", "tolerance", "t_e", "<D>", "error", "mu_sp", "error",
                             "wall s"])]
    for name in ("D", "mu_sp"):
        c = compare[name]
        lines.append(f"\n{name}: difference {c['difference']:.2e}, combined error "
                     f"{c['combined_error']:.2e}, within two errors: "
                     f"{c['within_two_errors']}")
    lines.append(f"largest |D| gap of one capsule up to t = 1: "
                 f"{compare['max_D_gap_to_t1']:.1e}; gap above 1e-3 from t = "
                 f"{compare['t_D_gap_above_1e-3']}")
    (OUT / f"agreement_{case}.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

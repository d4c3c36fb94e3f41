"""Speed-against-error report of the periodic single-layer evaluation (`capsim bench`).

Studies (each writes results/benchmarks/<study>_<case>.json, .md (table) and .png):
  accuracy  error against requested tolerance, strains 0 and 0.5
  speed     seconds per evaluation against achieved error
  (both for the methods given with --methods: spectral, direct, patches)
  scaling   seconds per evaluation against the number of sources (spectral)
  step      seconds per RK2 time step of `capsim run` (Ca 0.2, tolerance 1e-4 or
            --tolerance), per method
  precision spectral with its grids in double and single precision, tolerances 1e-3-1e-6
  real-space-precision  the same for the real-space sum (double grids)
  xi        spectral at its automatic xi and at 0.7-1.3 times it (--tolerance)
(the records the docs' tables are generated from, benchmarks/records/, are these JSON)
Usage: .venv/bin/python benchmarks/ewald_report.py STUDY [--capsules M] [--mesh-level N]
           [--methods spectral,direct,patches] [--tolerance T]
The error reference is direct Ewald at tolerance 1e-10 on the same configuration; it is
computed once per configuration and cached under results/benchmarks/.
"""

import argparse
import json
import pathlib
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from analysis.tables import markdown_table  # noqa: E402
from doc_tables import (ewald_scaling, ewald_speed, precision_table,  # noqa: E402
                        real_space_precision_table, xi_table)
from pipeline.run_spec import RunSpec  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "results" / "benchmarks"
CAPSIM = ROOT / "build" / "capsim"


def bench(capsules, level, method, tolerance, strain=0.0, phi=0.3, reference=True,
          repeats=2, xi=None, precision=None, real_space_precision=None):
    """One `capsim bench` run (xi None: the automatic one; a precision None: the bench's
    default, double); returns its JSON as a dict."""
    cmd = [str(CAPSIM), "bench", "--capsules", str(capsules), "--mesh-level", str(level),
           "--phi", str(phi), "--method", method, "--tolerance", str(tolerance),
           "--strain", str(strain), "--repeats", str(repeats)]
    if xi is not None:
        cmd += ["--xi", str(xi)]
    if precision is not None:
        cmd += ["--precision", precision]
    if real_space_precision is not None:
        cmd += ["--real-space-precision", real_space_precision]
    if reference:
        OUT.mkdir(parents=True, exist_ok=True)  # capsim writes the reference there
        ref = OUT / f"reference_M{capsules}_L{level}_phi{phi}_s{strain}.bin"
        cmd += ["--reference", str(ref)]
    else:
        cmd.append("--no-reference")
    print(" ".join(cmd[1:]), flush=True)
    return json.loads(subprocess.run(cmd, check=True, capture_output=True,
                                     text=True).stdout)


def save(name, rows, table):
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{name}.json").write_text(json.dumps(rows, indent=2) + "\n")
    (OUT / f"{name}.md").write_text(table)
    print(table)


def finish_plot(fig, ax, name, xlabel, ylabel, title, legend_size=None):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=legend_size)
    fig.tight_layout()
    fig.savefig(OUT / f"{name}.png", dpi=150)


MARKERS = {"spectral": "o", "direct": "s", "patches": "^"}
# Tolerances of the speed study: every decade for spectral, fewer for the slow methods.
SPEED_TOLERANCES = {"spectral": (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8),
                    "direct": (1e-2, 1e-4, 1e-6), "patches": (1e-2, 1e-4, 1e-6)}


def accuracy(capsules, level, methods):
    tolerances = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
    rows = [bench(capsules, level, method, tol, strain, repeats=1)
            for strain in (0.0, 0.5) for method in methods for tol in tolerances]
    table = pd.DataFrame(rows)[["method", "strain", "tolerance", "rel_error", "max_rel_error",
                                "seconds_per_eval"]]
    text = markdown_table(table, {"tolerance": ".0e", "rel_error": ".2e",
                                  "max_rel_error": ".2e", "seconds_per_eval": ".3f"},
                          ["method", "strain", "tolerance", "rel. error (RMS)",
                           "max rel. error", "s/eval"])
    name = f"accuracy_M{capsules}_L{level}" + suffix(methods)
    save(name, rows, text + "\n")
    fig, ax = plt.subplots(figsize=(5, 4))
    for method in methods:
        marker = MARKERS[method]
        for strain, fill in ((0.0, "full"), (0.5, "none")):
            sel = [r for r in rows if r["method"] == method and r["strain"] == strain]
            ax.loglog([r["tolerance"] for r in sel], [r["rel_error"] for r in sel],
                      marker=marker, fillstyle=fill, label=f"{method}, strain {strain}")
    ax.loglog(tolerances, tolerances, "k--", label="error = tolerance")
    finish_plot(fig, ax, name, "requested tolerance", "relative error (RMS over nodes)",
                f"M = {capsules}, level {level}, phi 0.3", legend_size=7)


def speed(capsules, level, methods):
    rows = [bench(capsules, level, method, tol, repeats=4 if method == "spectral" else 1)
            for method in methods for tol in SPEED_TOLERANCES[method]]
    text = ewald_speed(rows)
    name = f"speed_M{capsules}_L{level}" + suffix(methods)
    save(name, rows, text + "\n")
    fig, ax = plt.subplots(figsize=(5, 4))
    for method in methods:
        sel = [r for r in rows if r["method"] == method]
        ax.loglog([r["rel_error"] for r in sel], [r["seconds_per_eval"] for r in sel],
                  marker=MARKERS[method], label=method)
    finish_plot(fig, ax, name, "achieved relative error",
                "seconds per evaluation (2 cores)", f"M = {capsules}, level {level}, phi 0.3")


def scaling(level, tolerance=1e-4):
    per_capsule = 3 * 20 * 4**level
    counts = [c for c in (3, 9, 27, 81, 260) if c * per_capsule <= 1.1e6]
    rows = [bench(m, level, "spectral", tolerance, reference=False, repeats=1)
            for m in counts]
    sources = np.array([r["sources"] for r in rows], float)
    seconds = np.array([r["seconds_per_eval"] for r in rows])
    slope = np.polyfit(np.log(sources), np.log(seconds), 1)[0]
    name = f"scaling_L{level}"
    result = {"slope": slope, "runs": rows}
    save(name, result, ewald_scaling(result) + "\n")
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.loglog(sources, seconds, "o-", label=f"spectral, tol {tolerance:g}")
    ax.loglog(sources, seconds[0] * sources / sources[0], "k--", label="O(N)")
    finish_plot(fig, ax, name, "sources (3 per triangle)",
                "seconds per evaluation (2 cores)", f"level {level}, phi 0.3, slope {slope:.2f}")


def xi_scan(capsules, level, tolerance, factors=(0.7, 0.85, 1.15, 1.3)):
    """Spectral Ewald at the automatic xi and at `factors` times it: whether the automatic
    choice (spectral_xi's cost model) is the fastest in situ, at the same tolerance."""
    auto = bench(capsules, level, "spectral", tolerance, repeats=3)
    rows = [auto | {"automatic": True}] + [
        bench(capsules, level, "spectral", tolerance, repeats=3, xi=f * auto["xi"])
        | {"automatic": False} for f in factors]
    rows.sort(key=lambda r: r["xi"])
    name = f"xi_M{capsules}_L{level}"
    save(name, rows, xi_table(rows) + "\n")


def precision(capsules, level, tolerances=(1e-3, 1e-4, 1e-5, 1e-6)):
    """Spectral Ewald with its grids in double and in single precision (ewald.precision),
    side by side at each tolerance: the error each adds and the seconds each takes."""
    rows = [bench(capsules, level, "spectral", tol, repeats=4, precision=p)
            for tol in tolerances for p in ("double", "single")]
    save(f"precision_M{capsules}_L{level}", rows, precision_table(rows) + "\n")


def real_space_precision(capsules, level, tolerances=(1e-3, 1e-4, 1e-5, 1e-6)):
    """The real-space sum in double and in single precision (ewald.real_space_precision),
    double grids, side by side at each tolerance: the error each adds and the seconds."""
    rows = [bench(capsules, level, "spectral", tol, repeats=4, precision="double",
                  real_space_precision=p)
            for tol in tolerances for p in ("double", "single")]
    save(f"real_space_precision_M{capsules}_L{level}", rows,
         real_space_precision_table(rows) + "\n")


def step_run_spec(capsules, level, method, steps, tolerance):
    """A run of `steps` RK2 steps near the automatic dt, at Ca 0.2 and phi 0.3."""
    dt = 0.5 * 0.2 * {1: 0.62, 2: 0.31, 3: 0.155, 4: 0.078}[level]  # near the auto dt
    options = {"method": method, "ewald.tolerance": tolerance, "dt": dt}
    return RunSpec(study="benchmarks", ca=0.2, level=level, t_end=steps * dt,
                   t_avg_start=0, phi=0.3, M=capsules, snapshot_interval=0,
                   options=tuple(sorted(options.items())),
                   label=f"step_run_M{capsules}_L{level}_{method}_{steps}")


def run_wall_seconds(capsules, level, method, steps, tolerance):
    """Wall seconds of a `capsim run` of `steps` RK2 steps (setup included)."""
    spec = step_run_spec(capsules, level, method, steps, tolerance)
    out = ROOT / spec.folder
    subprocess.run(["rm", "-rf", str(out)], check=True)
    # threads 0: OpenMP's default, as capsim's own
    cmd, _ = spec.command(CAPSIM, threads=0, root=ROOT)
    print(" ".join(cmd[1:]), flush=True)
    subprocess.run(cmd, check=True)
    summary = json.loads((out / "summary.json").read_text())
    subprocess.run(["rm", "-rf", str(out)], check=True)
    return summary["wall_seconds"]


def step(capsules, level, methods, tolerance=1e-4):
    """Seconds per step: the difference of a 2-step and a 1-step run (no setup)."""
    rows = []
    for method in methods:
        one = run_wall_seconds(capsules, level, method, 1, tolerance)
        two = run_wall_seconds(capsules, level, method, 2, tolerance)
        rows.append({"method": method, "capsules": capsules, "mesh_level": level,
                     "tolerance": tolerance, "seconds_per_step": two - one,
                     "setup_seconds": 2 * one - two})
    table = pd.DataFrame(rows)[["method", "capsules", "mesh_level", "tolerance",
                                "seconds_per_step", "setup_seconds"]]
    text = markdown_table(table, {"tolerance": ".0e", "seconds_per_step": ".2f",
                                  "setup_seconds": ".2f"},
                          ["method", "capsules", "level", "tolerance", "s/step", "setup s"])
    name = f"step_M{capsules}_L{level}" + suffix(methods)
    if tolerance != 1e-4:
        name += f"_tol{tolerance:g}"
    save(name, rows, text + "\n")


def suffix(methods):
    """'' for every method, else '_' + the methods: a partial study keeps the full one."""
    return "" if set(methods) == set(MARKERS) else "_" + "_".join(methods)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("study",
                   choices=["accuracy", "speed", "scaling", "step", "xi", "precision",
                            "real-space-precision"])
    p.add_argument("--capsules", type=int, default=27)
    p.add_argument("--mesh-level", type=int, default=3)
    p.add_argument("--methods", default="spectral,direct,patches",
                   help="comma-separated methods for accuracy, speed and step")
    p.add_argument("--tolerance", type=float, default=1e-4,
                   help="step and xi: the Ewald tolerance")
    a = p.parse_args()
    methods = a.methods.split(",")
    if a.study == "accuracy":
        accuracy(a.capsules, a.mesh_level, methods)
    elif a.study == "speed":
        speed(a.capsules, a.mesh_level, methods)
    elif a.study == "step":
        step(a.capsules, a.mesh_level, methods, a.tolerance)
    elif a.study == "precision":
        precision(a.capsules, a.mesh_level)
    elif a.study == "real-space-precision":
        real_space_precision(a.capsules, a.mesh_level)
    elif a.study == "xi":
        xi_scan(a.capsules, a.mesh_level, a.tolerance)
    else:
        scaling(a.mesh_level)


if __name__ == "__main__":
    main()

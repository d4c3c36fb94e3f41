"""The CUDA backend against the CPU backend on the same machine: seconds per step and the
difference of the two trajectories, in one invocation.

    python3 benchmarks/backend_compare.py [--threads 16] [--cases dilute_l4,...] [--out F]

Each case runs `capsim run --profile` with `backend: cpu` on --threads OpenMP threads and
then with `backend: cuda` (whose host part, the volume constraint and the diagnostics, uses
the same threads), from the same start over the same strain. It reports the seconds per
step of each (the profile's time-loop seconds, set-up excluded), their ratio, the device
run's stages, and how far the trajectories part: the largest difference of each capsule
time series (D, the stresslet) relative to its largest value, of the centroids in units
of a, and the
averages <D> and mu_sp of both. The CPU run takes the device run's Ewald splitting
(ewald.xi), which the device may choose smaller (docs/gpu.md), so that the difference is
the backends' and not the Ewald error's. Both backends take the same steps (dt follows the mesh),
so the two time series are compared sample by sample. The backend needs lumped loads
and no bending (docs/gpu.md); it has the repulsion, but the suspension cases run without
it, as they were first measured. Run it on an otherwise idle machine with a GPU.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from analysis.read_run import read_summary, read_timeseries  # noqa: E402
from pipeline.command_line import run_command  # noqa: E402

# Double grids on both backends (the device has no single ones), so that the two compute
# the same sums.
SUSPENSION = {"ca": 0.2, "phi": 0.3, "seed": 1, "ewald.tolerance": "auto",
              "ewald.precision": "double", "dt_safety": 1, "time.scheme": "heun",
              "output.snapshot_interval": 0}
CASES = {  # name: options (t_end sets the length: tens of steps each)
    "dilute_l4": {"ca": 0.2, "phi": 0, "capsules": 1, "mesh_level": 4, "t_end": 1.0},
    "suspension_M27_l3": {**SUSPENSION, "capsules": 27, "mesh_level": 3, "t_end": 1.0},
    "suspension_M27_l4": {**SUSPENSION, "capsules": 27, "mesh_level": 4, "t_end": 0.25},
    "suspension_M100_l3": {**SUSPENSION, "capsules": 100, "mesh_level": 3, "t_end": 0.25},
}
SERIES = ("D", "stresslet", "centroid")


def run(capsim, options, backend, threads, scratch):
    out = Path(scratch) / backend
    profile = out.with_suffix(".json")
    settings = {**options, "t_avg_start": 0, "threads": threads, "backend": backend,
                "output.checkpoint_interval": options["t_end"]}
    start = time.perf_counter()
    subprocess.run(run_command(capsim, settings, out, "-q", "--profile", str(profile)),
                   check=True, env={"OMP_WAIT_POLICY": "passive", **os.environ})
    return {"wall_s": time.perf_counter() - start, "profile": json.loads(profile.read_text()),
            "summary": read_summary(out), "series": read_timeseries(out)}


def parted(cpu, cuda):
    """Largest difference of each time series relative to its largest value; of the
    centroids in units of the radius a (one capsule's stays near 0)."""
    scale = {k: np.max(np.abs(cpu[k])) for k in SERIES} | {"centroid": 1.0}
    return {k: float(np.max(np.abs(cuda[k] - cpu[k])) / scale[k]) for k in SERIES}


def compare(capsim, name, threads):
    with tempfile.TemporaryDirectory() as scratch:
        runs = {"cuda": run(capsim, CASES[name], "cuda", threads, scratch)}
        xi = runs["cuda"]["summary"].get("ewald_xi")  # the device may cap r_cut lower
        same = {**CASES[name], "ewald.xi": xi} if xi else CASES[name]
        runs["cpu"] = run(capsim, same, "cpu", threads, scratch)
    cpu, cuda = (runs[b] for b in ("cpu", "cuda"))
    step = {b: runs[b]["profile"]["seconds_per_step"]["loop"] for b in runs}
    return {
        "options": CASES[name], "steps": cuda["profile"]["steps"],
        "seconds_per_step": step, "speedup": step["cpu"] / step["cuda"],
        "wall_s": {b: runs[b]["wall_s"] for b in runs},
        "stages_seconds_per_step": {b: runs[b]["profile"]["seconds_per_step"] for b in runs},
        "difference": parted(cpu["series"], cuda["series"]),
        "averages": {b: {k: runs[b]["summary"][k] for k in ("taylor_D", "mu_sp")}
                     for b in runs},
        "volume_error_max": {b: runs[b]["summary"]["volume_error_max"] for b in runs},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--capsim", default=str(ROOT / "build" / "capsim"))
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated, of: "
                    + ", ".join(CASES))
    ap.add_argument("--out", help="also write the JSON here")
    args = ap.parse_args()
    result = {"threads": args.threads, "cases": {}}
    for name in args.cases.split(","):
        entry = compare(args.capsim, name, args.threads)
        result["cases"][name] = entry
        s = entry["seconds_per_step"]
        print(f"{name}: {entry['steps']} steps, cpu {s['cpu']:.4f} s/step, cuda "
              f"{s['cuda']:.4f} s/step, speed-up {entry['speedup']:.1f}; differences "
              + ", ".join(f"{k} {v:.1e}" for k, v in entry["difference"].items()),
              file=sys.stderr, flush=True)
        if args.out:  # after every case, so that a cut-off invocation keeps what it did
            Path(args.out).parent.mkdir(parents=True, exist_ok=True)
            Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()

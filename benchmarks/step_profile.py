"""Where one step of the workflow's runs spends its time, measured in the run itself
(`capsim run --profile`), and each stage's rate against its own bound.

    .venv/bin/python benchmarks/step_profile.py [--out results/benchmarks/step_profile.json]

The cases: the Table 1 point (Ca 0.2, phi 0.3, M 27) at level 3 and at level 4 with the
quantitative configuration's settings (Heun at dt_safety 1, ewald.tolerance auto, the
repulsion F0 = 1 over 0.1), a few steps each from rest. For every stage: seconds per step
and share of the step, the growth from level 3 to level 4, and a rate against a bound:
- real space: GFLOP/s at 145 flops per (target, source) pair (the kernel's count,
  benchmarks/bench_screened_kernel.cpp) against the FMA peak (build/peak_flops);
- FFT: GFLOP/s by FFTW's convention (2.5 N log2 N per real transform of N points; three
  forward and three backward per evaluation) against the same peak;
- spreading and gathering: GB/s of the grid values they touch (P^3 per source point and
  component, read and written when spreading, read when gathering) against the memory
  bandwidth of a large copy (numpy, measured here).
Run it on an otherwise idle machine: JSON on stdout (and in --out), a table on stderr.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pipeline.command_line import run_command

ROOT = Path(__file__).resolve().parents[1]
CAPSIM = ROOT / "build" / "capsim"
PEAK = ROOT / "build" / "peak_flops"
FLOPS_PER_PAIR = 145
RULE_POINTS = 3  # far-rule points per triangle: the spreading's sources
CASE = {"ca": 0.2, "phi": 0.3, "capsules": 27, "seed": 1, "ewald.tolerance": "auto",
        "suspension.repulsion_force": 1, "suspension.repulsion_range": 0.1,
        "dt_safety": 1, "time.scheme": "heun", "output.snapshot_interval": 0}
LEVELS = {3: 0.25, 4: 0.05}  # mesh level: t_end (about 12 and 5 steps)


def print_json(result, out=None):
    """Prints a benchmark's JSON, and writes it to `out` as well when given."""
    text = json.dumps(result, indent=1)
    if out:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        Path(out).write_text(text + "\n")
    print(text)


def profile_run(level, t_end, threads):
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / "run"
        options = {**CASE, "mesh_level": level, "t_end": t_end, "t_avg_start": 0,
                   "threads": threads, "output.checkpoint_interval": t_end}
        start = time.perf_counter()
        subprocess.run(run_command(CAPSIM, options, out, "-q", "--profile",
                                   str(Path(scratch) / "profile.json")), check=True,
                       env={"OMP_WAIT_POLICY": "passive", **os.environ})
        wall = time.perf_counter() - start
        profile = json.loads((Path(scratch) / "profile.json").read_text())
        summary = json.loads((out / "summary.json").read_text())
    return profile, summary, wall


def memory_bandwidth():
    """GB/s of a 256 MB copy (read and write counted), the best of five."""
    a = np.ones(32 * 2**20)
    b = np.empty_like(a)
    best = min(_timed(lambda: np.copyto(b, a)) for _ in range(5))
    return 2 * a.nbytes / best / 1e9


def _timed(f):
    start = time.perf_counter()
    f()
    return time.perf_counter() - start


def fma_peak(threads):
    if not PEAK.exists():
        return None
    peaks = json.loads(subprocess.run([str(PEAK)], capture_output=True, text=True,
                                      check=True).stdout)["gflops"]
    return peaks.get(str(threads)) or max(peaks.values())


def rates(profile, summary, level):
    """Each stage's rate from its seconds and the run's sizes."""
    per_eval = {k: v / profile["evaluations"] for k, v in profile["seconds"].items()}
    triangles = 20 * 4**level * summary["parameters"]["capsules"]
    grid = summary["spectral_grid"]
    points = math.prod(grid)
    support = summary["spectral_support"]
    # The precisions `auto` took (summary.json; a run before they were recorded: double).
    grid_precision = summary.get("spectral_precision", "double")
    value_bytes = 4 if grid_precision == "single" else 8
    touched = RULE_POINTS * triangles * 3 * support**3 * value_bytes  # one pass
    return {
        "real_space_gflops": profile["real_space_pairs_per_evaluation"] * FLOPS_PER_PAIR
        / per_eval["real_space"] / 1e9,
        "fft_gflops": 6 * 2.5 * points * math.log2(points) / per_eval["fft"] / 1e9,
        "spreading_gbytes_per_s": 2 * touched / per_eval["spreading"] / 1e9,
        "gathering_gbytes_per_s": touched / per_eval["gathering"] / 1e9,
        "grid": grid, "support": support, "source_points": RULE_POINTS * triangles,
        "grid_precision": grid_precision,
        "real_space_precision": summary.get("real_space_precision", "double"),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", help="also write the JSON here")
    args = ap.parse_args()
    result = {"case": CASE, "threads": args.threads, "fma_peak_gflops":
              fma_peak(args.threads), "memory_gbytes_per_s": memory_bandwidth(),
              "levels": {}}
    for level, t_end in LEVELS.items():
        profile, summary, wall = profile_run(level, t_end, args.threads)
        step = profile["seconds_per_step"]["loop"]
        result["levels"][level] = {
            "steps": profile["steps"], "wall_seconds": wall,
            "seconds_per_step": profile["seconds_per_step"],
            "share_of_step": {k: v / step for k, v in profile["seconds_per_step"].items()},
            "seconds_per_strain": step / summary["dt"],
            "seconds_per_capsule_strain": step / summary["dt"] / CASE["capsules"],
            "rates": rates(profile, summary, level)}
    l3, l4 = (result["levels"][k]["seconds_per_step"] for k in (3, 4))
    result["growth_level3_to_4"] = {k: l4[k] / l3[k] for k in l3 if l3[k] > 0}
    print_json(result, args.out)
    print(f"{'stage':<24}{'l3 s/step':>11}{'share':>7}{'l4 s/step':>11}{'share':>7}"
          f"{'growth':>8}", file=sys.stderr)
    for k in l3:
        s3, s4 = (result["levels"][lv]["share_of_step"][k] for lv in (3, 4))
        print(f"{k:<24}{l3[k]:11.4f}{s3:7.1%}{l4[k]:11.4f}{s4:7.1%}"
              f"{result['growth_level3_to_4'].get(k, float('nan')):8.1f}", file=sys.stderr)


if __name__ == "__main__":
    main()

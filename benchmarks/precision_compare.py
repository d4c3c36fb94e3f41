"""Two settings of capsim side by side on the workflow's runs: speed and accuracy in one
invocation; by default single-precision Spectral-Ewald grids against double.

    .venv/bin/python benchmarks/precision_compare.py [--out results/benchmarks/precision.json]
        [--baseline KEY=VALUE ...] [--candidate KEY=VALUE ...]

For each case (the Table 1 point at level 3 over 3 strain units and at level 4 over 0.5,
the quantitative configuration's settings: benchmarks/step_profile.py) it runs capsim with
the baseline's options and the candidate's (default `ewald.precision` double and single),
one after the other (so each ratio is measured on the same machine minutes apart), and
reports wall and CPU seconds per capsule per unit strain with the in-situ seconds of every
stage, the averages <D> and mu_sp over the second half of each run with their standard
errors (analysis.averages) and their difference in units of the standard error; and, for
the precisions (of the grids, of the real-space sum), from `capsim bench` (M 27
stretched capsules at the same phi and level) the velocity error of each against a tight
direct-Ewald reference at the tolerance the runs use. Run it on an otherwise idle machine.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from analysis.averages import run_averages
from analysis.read_run import read_summary, read_timeseries
from analysis.rheology import rheology
from pipeline.command_line import run_command

sys.path.insert(0, str(Path(__file__).resolve().parent))
from step_profile import CAPSIM, CASE, print_json  # noqa: E402

CASES = {3: 3.0, 4: 0.5}  # mesh level: strain units


def run(level, t_end, threads, out, capsim=CAPSIM, **options):
    """One run of the Table 1 case (CASE) at `level` to `t_end` in folder `out`, with
    further capsim options: its cost per capsule-strain, the in-situ seconds of the
    reciprocal stages and its averages over the second half with standard errors."""
    out = Path(out)
    profile = out.with_suffix(".json")
    settings = {**CASE, "mesh_level": level, "t_end": t_end, "t_avg_start": t_end / 2,
                "threads": threads, **options}
    start, cpu = time.perf_counter(), os.times()
    subprocess.run(run_command(capsim, settings, out, "-q", "--profile", str(profile)),
                   check=True, env={"OMP_WAIT_POLICY": "passive", **os.environ})
    wall = time.perf_counter() - start
    after = os.times()
    cpu_s = after.children_user + after.children_system - cpu.children_user - cpu.children_system
    summary = read_summary(out)
    avg = run_averages(read_timeseries(out), t_end / 2)
    mu = rheology(avg["stresslet"], CASE["phi"], CASE["ca"])["mu_sp"]
    mu_se = abs(mu / avg["stresslet"][0, 1]) * avg["stresslet_se"][0, 1]
    profiled = json.loads(profile.read_text())
    seconds = profiled["seconds"]
    per = CASE["capsules"] * t_end
    return {"wall_s_per_capsule_strain": wall / per, "cpu_s_per_capsule_strain": cpu_s / per,
            "reciprocal_s": seconds["reciprocal"], "fft_s": seconds["fft"],
            "spreading_s": seconds["spreading"], "gathering_s": seconds["gathering"],
            "D": avg["D"], "D_se": float(avg["D_se"]), "mu_sp": float(mu),
            "mu_sp_se": float(mu_se), "tolerance": summary["parameters"]["ewald.tolerance"],
            "seconds_per_step": profiled["seconds_per_step"]}


# The precision keys `capsim bench` takes as flags; a setting without one has the run's
# default, auto.
BENCH_FLAGS = {"ewald.precision": "--precision",
               "ewald.real_space_precision": "--real-space-precision"}


def velocity_error(level, tolerance, setting, threads, reference):
    flags = [a for key, flag in BENCH_FLAGS.items() for a in (flag, setting.get(key, "auto"))]
    out = subprocess.run([str(CAPSIM), "bench", "--capsules", str(CASE["capsules"]),
                          "--mesh-level", str(level), "--phi", str(CASE["phi"]),
                          "--tolerance", str(tolerance), *flags,
                          "--threads", str(threads), "--repeats", "1", "--reference",
                          str(reference)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)["rel_error"]


def options(pairs):
    """{key: value} of KEY=VALUE arguments."""
    return dict(p.split("=", 1) for p in pairs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--baseline", nargs="+", default=["ewald.precision=double"])
    ap.add_argument("--candidate", nargs="+", default=["ewald.precision=single"])
    ap.add_argument("--out", help="also write the JSON here")
    args = ap.parse_args()
    settings = {"baseline": options(args.baseline), "candidate": options(args.candidate)}
    result = {"case": CASE, "threads": args.threads, "settings": settings, "levels": {}}
    with tempfile.TemporaryDirectory() as scratch:
        for level, strain in CASES.items():
            runs = {w: run(level, strain, args.threads, Path(scratch) / f"l{level}_{w}", **o)
                    for w, o in settings.items()}
            d, s = runs["baseline"], runs["candidate"]
            entry = {"strain": strain, "runs": runs,
                     "wall_ratio": s["wall_s_per_capsule_strain"] / d["wall_s_per_capsule_strain"],
                     "cpu_ratio": s["cpu_s_per_capsule_strain"] / d["cpu_s_per_capsule_strain"],
                     "D_difference_in_se": abs(s["D"] - d["D"]) / d["D_se"],
                     "mu_sp_difference_in_se": abs(s["mu_sp"] - d["mu_sp"]) / d["mu_sp_se"]}
            if all(set(o) <= set(BENCH_FLAGS) for o in settings.values()):
                ref = Path(scratch) / f"reference_l{level}.h5"
                entry["velocity_error"] = {
                    w: velocity_error(level, d["tolerance"], o, args.threads, ref)
                    for w, o in settings.items()}
            result["levels"][level] = entry
            print(f"level {level}: tolerance {d['tolerance']:.3g}, wall ratio "
                  f"{entry['wall_ratio']:.3f}, CPU ratio {entry['cpu_ratio']:.3f}; <D> "
                  f"{d['D']:.6f} / {s['D']:.6f} ({entry['D_difference_in_se']:.2g} SE), "
                  f"mu_sp {d['mu_sp']:.5f} / {s['mu_sp']:.5f} "
                  f"({entry['mu_sp_difference_in_se']:.2g} SE)", file=sys.stderr)
    print_json(result, args.out)


if __name__ == "__main__":
    main()

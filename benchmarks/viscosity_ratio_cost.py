"""The cost of another viscosity inside (lambda != 1) against lambda = 1, one capsule in
unbounded shear or (--capsules, --phi) a suspension, in one invocation on the same
machine, and the error of the solve's tolerance (and time scheme) against a tight one.

    python3 benchmarks/viscosity_ratio_cost.py [--levels 2 3] [--lambdas 1 0.2 5 10]
        [--ca 0.2] [--strain 1] [--capsules 1 --phi 0] [--threads 2]
        [--gmres-tolerances T ...] [--gmres-guesses G ...] [--time-schemes S ...]
        [--reference-tolerance 1e-10] [--reference-dt-safety 1]
        [--out benchmarks/records/F.json]

Each case runs `capsim run --profile` from the same start over the same strain, and
reports the time loop's seconds per capsule-strain (set-up excluded), the steps and
evaluations, the second-kind solves (an output's solve serves the next step's first
evaluation), the GMRES iterations per solve and the largest residual (summary.json),
and the ratio of each cost to lambda = 1 at the same mesh. Each lambda != 1 runs at
every gmres.tolerance T, gmres.guess G and time scheme S (heun; rkcN: time.scheme
rkc of N stages; imexT: time.scheme imex at time.tolerance T; capsim's defaults unless
given; those cases are marked default_tolerance, default_guess and default_scheme: the
cost model reads the case with all three) and once as the reference: Heun at the
reference tolerance, with dt_safety --reference-dt-safety (below 1 where the time
scheme's error is to be seen too);
the record gives each cost and what T, G and S change against the reference: the largest
node displacement at the end and the largest differences of D and of the stresslet
over all samples (the mesh's own error in D is about 1e-2 at level 2, 5e-3 at level 3).
Run it on an otherwise idle machine.
"""

import argparse
import itertools
import json
import platform
import subprocess
import sys
import tempfile
from datetime import date
from pathlib import Path

import h5py
import numpy as np
from scipy.interpolate import CubicSpline

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from analysis.accuracy import time_options  # noqa: E402
from analysis.read_run import read_summary, read_timeseries  # noqa: E402
from pipeline.command_line import run_command  # noqa: E402


def scheme_keys(name):
    """capsim's keys of a --time-schemes word: default (none), heun, rkcN or imexT."""
    if name in ("default", "heun"):
        return {} if name == "default" else {"time.scheme": "heun"}
    stages = name.removeprefix("rkc")
    if name.startswith("rkc") and stages.isdigit():
        return {"time.scheme": "rkc", "time.stages": int(stages)}
    if name.startswith("imex"):  # the accuracy study's time codes (imex<T>, imexrms<T>)
        try:
            return dict(option.split("=", 1) for option in time_options(name))
        except ValueError:
            pass
    raise argparse.ArgumentTypeError(f"{name!r}: not default, heun, rkcN (N stages) or "
                                     "imexT (time.tolerance T)")


def run_case(capsim, level, lam, ca, strain, threads, scratch, capsules=1, phi=0.0,
             keys=None):
    """One timed run; `keys`: further capsim keys (None values are left out)."""
    keys = {k: v for k, v in (keys or {}).items() if v is not None}
    out = Path(scratch) / "_".join([f"l{level}_lambda{lam:g}",
                                    *(f"{k}{v}" for k, v in sorted(keys.items()))])
    profile = out.parent / (out.name + ".profile.json")
    settings = {"ca": ca, "mesh_level": level, "lambda": lam, "t_end": strain,
                "t_avg_start": 0, "threads": threads, "capsules": capsules, "phi": phi,
                "output.checkpoint_interval": strain, "output.snapshot_interval": 0,
                **keys}
    subprocess.run(run_command(capsim, settings, out, "-q", "--profile", str(profile)),
                   check=True)
    prof, summary = json.loads(profile.read_text()), read_summary(out)
    strain_run = float(summary["t_end"])
    case = {"mesh_level": level, "lambda": lam, "capsules": capsules, "phi": phi,
            "gmres_tolerance": summary["parameters"].get("gmres.tolerance"),
            "gmres_guess": summary["parameters"].get("gmres.guess"),
            "time_scheme": scheme_name(summary["parameters"]),
            "dt_safety": summary["parameters"].get("dt_safety"),
            "strain": strain_run, "steps": prof["steps"],
            "evaluations": prof["evaluations"],
            "seconds_per_strain": prof["seconds"]["loop"] / strain_run / capsules,
            "gmres_solves": summary.get("gmres_solves", 0),
            "gmres_iterations_mean": summary.get("gmres_iterations_mean", 0.0),
            "gmres_iterations_max": summary.get("gmres_iterations_max", 0),
            "gmres_residual_max": summary.get("gmres_residual_max", 0.0)}
    return case, out


def scheme_name(parameters):
    """heun, imexT or rkcN, from a run's resolved parameters."""
    scheme = parameters.get("time.scheme", "heun")
    if scheme == "imex":
        return f"imex{float(parameters['time.tolerance']):g}"
    return f"rkc{parameters['time.stages']}" if scheme == "rkc" else scheme


def scale(run):
    """What the differences are read against: the mean |D| and the largest mean |S_ij|
    of the stresslet's components over the run's samples and capsules."""
    ts = read_timeseries(run)
    return {"D": float(np.abs(ts["D"]).mean()),
            "stresslet": float(np.abs(ts["stresslet"]).mean(axis=(0, 1)).max())}


def difference(run, reference):
    """What separates a run from the reference: the largest differences of D and of the
    stresslet over the run's samples, the reference (sampled at every step) interpolated
    to their times by a cubic spline (exact where the steps agree), and the largest node
    displacement at the end (None where the two end at other times: another step)."""
    sa, sb = read_timeseries(run), read_timeseries(reference)
    t = sa["time"][sa["time"] <= sb["time"][-1]]
    at = {key: CubicSpline(sb["time"], sb[key], axis=0)(t) for key in ("D", "stresslet")}
    x = None
    if sa["time"][-1] == sb["time"][-1]:
        with h5py.File(run / "checkpoint.h5") as a, \
                h5py.File(reference / "checkpoint.h5") as b:
            x = float(np.abs(a["positions"][()] - b["positions"][()]).max())
    return {"position": x,
            "D": float(np.abs(sa["D"][:len(t)] - at["D"]).max()),
            "stresslet": float(np.abs(sa["stresslet"][:len(t)] - at["stresslet"]).max())}


def public_arguments(argv):
    """The command line without --capsim and its value (a path of this machine's)."""
    out, skip = [], False
    for word in argv:
        if skip or word.startswith("--capsim="):
            skip = False
            continue
        skip = word == "--capsim"
        if not skip:
            out.append(word)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--capsim", default=str(ROOT / "build" / "capsim"))
    ap.add_argument("--levels", type=int, nargs="+", default=[2, 3])
    ap.add_argument("--lambdas", type=float, nargs="+", default=[1.0, 0.2, 5.0, 10.0])
    ap.add_argument("--ca", type=float, default=0.2)
    ap.add_argument("--strain", type=float, default=1.0)
    ap.add_argument("--capsules", type=int, default=1, help="capsules per box")
    ap.add_argument("--phi", type=float, default=0.0, help="volume fraction (0: one "
                    "capsule in unbounded shear)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--gmres-tolerances", type=float, nargs="+", default=[None],
                    help="gmres.tolerance of the timed cases (default: capsim's)")
    ap.add_argument("--gmres-guesses", nargs="+", default=["default"],
                    choices=["default", "previous", "extrapolated"],
                    help="gmres.guess of the timed cases (default: capsim's)")
    ap.add_argument("--time-schemes", nargs="+", default=["default"], type=str,
                    help="time schemes of the timed cases: default (capsim's), heun, "
                    "rkcN (time.scheme rkc of N stages) or imexT (time.scheme imex at "
                    "time.tolerance T)")
    ap.add_argument("--reference-dt-safety", type=float, default=1.0,
                    help="dt_safety of the reference (Heun): below 1 to see the time "
                    "schemes' error too")
    ap.add_argument("--reference-tolerance", type=float, default=1e-10,
                    help="gmres.tolerance of the reference each lambda != 1 is "
                    "compared with")
    ap.add_argument("--out", help="write the record here (JSON)")
    args = ap.parse_args(argv)
    if 1.0 not in args.lambdas:
        ap.error("--lambdas must include 1, the baseline")
    try:
        schemes = {name: scheme_keys(name) for name in args.time_schemes}
    except argparse.ArgumentTypeError as e:
        ap.error(f"--time-schemes: {e}")
    cases = []
    with tempfile.TemporaryDirectory() as scratch:
        for level in args.levels:
            for lam in args.lambdas:
                common = (args.capsim, level, lam, args.ca, args.strain, args.threads,
                          scratch, args.capsules, args.phi)
                if lam == 1.0:
                    cases.append(run_case(*common)[0])
                    continue
                ref, ref_out = run_case(*common, keys={
                    "gmres.tolerance": args.reference_tolerance, "time.scheme": "heun",
                    "dt_safety": args.reference_dt_safety,
                    "output.sample_interval": 1e-9})  # every step
                ref["scale"] = scale(ref_out)
                for tolerance, guess, scheme in itertools.product(
                        args.gmres_tolerances, args.gmres_guesses, schemes):
                    given = None if guess == "default" else guess
                    case, out = run_case(*common, keys={
                        "gmres.tolerance": tolerance, "gmres.guess": given,
                        **schemes[scheme]})
                    case["default_tolerance"] = tolerance is None
                    case["default_guess"] = given is None
                    case["default_scheme"] = scheme == "default"
                    case["reference"] = ref
                    case["difference_from_reference"] = difference(out, ref_out)
                    cases.append(case)
    for case in cases:
        base = next(c for c in cases if c["mesh_level"] == case["mesh_level"]
                    and c["lambda"] == 1.0)
        case["cost_ratio"] = case["seconds_per_strain"] / base["seconds_per_strain"]
        print(f"level {case['mesh_level']} lambda {case['lambda']:g} "
              f"(gmres.tolerance {case['gmres_tolerance']}, "
              f"guess {case['gmres_guess']}, {case['time_scheme']}): "
              f"{case['seconds_per_strain']:.3g} s per capsule-strain "
              f"({case['cost_ratio']:.2f} x lambda 1), {case['steps']} steps, "
              f"GMRES {case['gmres_iterations_mean']:.1f} per solve "
              f"(max {case['gmres_iterations_max']}, residual "
              f"{case['gmres_residual_max']:.1e})")
        if "reference" in case:
            ref = case["reference"]
            ref["cost_ratio"] = ref["seconds_per_strain"] / base["seconds_per_strain"]
            d = case["difference_from_reference"]
            x = "-" if d["position"] is None else f"{d['position']:.1e}"
            print(f"  against gmres.tolerance {ref['gmres_tolerance']} "
                  f"(heun, dt_safety {ref['dt_safety']}): "
                  f"{ref['cost_ratio']:.2f} x lambda 1, GMRES "
                  f"{ref['gmres_iterations_mean']:.1f}; differences: positions {x}, "
                  f"D {d['D']:.1e} (of {ref['scale']['D']:.2f}), stresslet "
                  f"{d['stresslet']:.1e} (of {ref['scale']['stresslet']:.2f})")
    if args.out:
        record = {"benchmark": "viscosity_ratio_cost", "date": date.today().isoformat(),
                  "machine": f"{platform.processor() or platform.machine()}, "
                             f"{args.threads} threads",
                  "command": "python3 benchmarks/viscosity_ratio_cost.py " +
                             " ".join(public_arguments(argv if argv is not None
                                                       else sys.argv[1:])),
                  "ca": args.ca, "cases": cases}
        Path(args.out).write_text(json.dumps(record, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

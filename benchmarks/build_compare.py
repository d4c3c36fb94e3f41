"""Two builds of capsim side by side on the workflow's runs: speed and accuracy in one
invocation, for a change that should make a step cheaper.

    .venv/bin/python benchmarks/build_compare.py --old OLD/capsim [--new build/capsim]
        [--old-label COMMIT] [--set KEY=VALUE ...] [--new-set KEY=VALUE ...]
        [--cases LEVEL:STRAIN ...] [--out results/benchmarks/build_compare.json]

OLD is a capsim built from the commit to compare with (for example in a git worktree:
`git worktree add /tmp/old <commit> && bash scripts/setup.sh` there). For the Table 1
point at the quantitative configuration's settings (benchmarks/step_profile.py: Heun at
dt_safety 1, ewald.tolerance auto, the repulsion) at level 3 over 2 strain units and at
level 4 over 0.3, it runs old, new, new, old (so that a drift of the machine falls on
both alike) and reports, per build, the wall and CPU seconds per capsule per unit strain
(the mean of its two runs), the ratio old / new, the in-situ seconds per step of every
stage, and the accuracy: whether the two builds' time series are identical, else the
largest difference of D and the stresslet relative to their largest values, and the
averages <D> and mu_sp over the second half with their standard errors. --new-set gives
the new build further capsim options (a setting the old one lacks, e.g. time.scheme=rkc),
--set both builds (e.g. lambda=5 gmres.tolerance=1e-5, the dense viscosity-ratio study's
settings); --cases replaces the meshes and strains (e.g. 3:0.5).
Run it on an otherwise idle machine.
"""

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from analysis.read_run import read_timeseries

sys.path.insert(0, str(Path(__file__).resolve().parent))
from precision_compare import run  # noqa: E402
from step_profile import CAPSIM, print_json  # noqa: E402

CASES = {3: 2.0, 4: 0.3}  # mesh level: strain units
ORDER = ("old", "new", "new", "old")


def difference(a, b):
    """Largest difference of D and the stresslet series relative to their largest value
    (0 where the two builds give the same bits), over the sample times both have after
    the start; where they share none (another time step samples at other times), b
    interpolated linearly to a's times within b's span ("interpolated": true)."""
    ia, ib = (np.nonzero(np.isin(np.round(x["time"], 9), np.round(y["time"], 9)))[0][1:]
              for x, y in ((a, b), (b, a)))
    if len(ia):
        return {k: float(np.max(np.abs(a[k][ia] - b[k][ib])) / np.max(np.abs(a[k])))
                for k in ("D", "stresslet")}
    t = a["time"][1:][a["time"][1:] <= b["time"][-1]]
    out = {"interpolated": True}
    for k in ("D", "stresslet"):
        flat_a, flat_b = (x[k].reshape(len(x["time"]), -1) for x in (a, b))
        at = np.column_stack([np.interp(t, b["time"], col) for col in flat_b.T])
        rows = np.isin(a["time"], t)
        out[k] = float(np.max(np.abs(flat_a[rows] - at)) / np.max(np.abs(flat_a)))
    return out


def level_strain(text):
    """A --cases word LEVEL:STRAIN as (int, float)."""
    level, _, strain = text.partition(":")
    try:
        return int(level), float(strain)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: not LEVEL:STRAIN (e.g. 3:0.5)")


def compare(level, strain, builds, threads, scratch, options, new_options):
    runs = {"old": [], "new": []}
    for k, which in enumerate(ORDER):
        out = Path(scratch) / f"l{level}_{which}{k}"
        extra = {**options, **(new_options if which == "new" else {})}
        runs[which].append(run(level, strain, threads, out, capsim=builds[which],
                               **extra))
        runs[which][-1]["series"] = read_timeseries(out)
    per = {w: {key: float(np.mean([r[key] for r in rs]))
               for key in ("wall_s_per_capsule_strain", "cpu_s_per_capsule_strain")}
           for w, rs in runs.items()}
    old, new = runs["old"][0], runs["new"][0]
    return {"strain": strain, "builds": per,
            "wall_ratio": per["old"]["wall_s_per_capsule_strain"]
            / per["new"]["wall_s_per_capsule_strain"],
            "cpu_ratio": per["old"]["cpu_s_per_capsule_strain"]
            / per["new"]["cpu_s_per_capsule_strain"],
            "seconds_per_step": {w: rs[0]["seconds_per_step"] for w, rs in runs.items()},
            "difference": difference(old["series"], new["series"]),
            "averages": {w: {k: rs[0][k] for k in ("D", "D_se", "mu_sp", "mu_sp_se")}
                         for w, rs in runs.items()}}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--old", required=True, help="the capsim to compare with")
    ap.add_argument("--new", default=str(CAPSIM))
    ap.add_argument("--old-label", default="old build",
                    help="how the record names the old build (e.g. its commit)")
    ap.add_argument("--new-label", default="this checkout's build",
                    help="how the record names the new build")
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="further capsim options of both builds' runs")
    ap.add_argument("--new-set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="further capsim options of the new build's runs")
    ap.add_argument("--cases", nargs="+", type=level_strain, metavar="LEVEL:STRAIN",
                    default=list(CASES.items()),
                    help="mesh levels and strains (default: 3:2 4:0.3)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", help="also write the JSON here")
    args = ap.parse_args()
    builds = {"old": args.old, "new": args.new}
    options = dict(o.split("=", 1) for o in args.set)
    new_options = dict(o.split("=", 1) for o in args.new_set)
    # The record names the builds by label, not by path (a path is of one machine).
    result = {"builds": {"old": args.old_label, "new": args.new_label},
              "options": options, "new_options": new_options, "threads": args.threads, "levels": {}}
    with tempfile.TemporaryDirectory() as scratch:
        for level, strain in args.cases:
            entry = compare(level, strain, builds, args.threads, scratch, options,
                            new_options)
            result["levels"][level] = entry
            print(f"level {level}: wall ratio old/new {entry['wall_ratio']:.3f}, CPU ratio "
                  f"{entry['cpu_ratio']:.3f}; differences " + ", ".join(
                      f"{k} {v:.1e}" for k, v in entry["difference"].items()
                      if k != "interpolated"),
                  file=sys.stderr, flush=True)
    print_json(result, args.out)


if __name__ == "__main__":
    main()

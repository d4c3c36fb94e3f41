"""Order of the time schemes: one capsule in simple shear from rest, the largest error of
D and of the stresslet's S_xy at a few fixed strains against a run with a much smaller
step, for fixed steps spanning more than a decade.

Usage: .venv/bin/python benchmarks/time_order.py [--mesh-level N] [--ca 0.05,0.2,0.6]
           [--schemes imex,heun] [--strain T] [--steps 5,10,20,40,80] [--reference 2560]
Writes results/benchmarks/time_order.json and .md. The reference is `--reference-scheme`
(heun) at `--reference` steps (its own error is (max steps / reference)^2 of the finest
run's).
A step count at which a scheme is unstable (the run stops, exit 3) is listed as such.
"""

import argparse
import json
import math
import pathlib
import subprocess
import tempfile

import numpy as np
import pandas as pd

from analysis.read_run import read_timeseries
from analysis.tables import markdown_table
from pipeline.command_line import run_command
from pipeline.run_spec import RunSpec

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "results" / "benchmarks"


def fixed_step_spec(a, ca, scheme, steps):
    """A run of `steps` fixed steps of `scheme` to strain a.strain."""
    options = {"dt": a.strain / steps, "time.scheme": scheme,
               "output.sample_interval": a.strain / a.samples,
               "output.snapshot_interval": 0}
    return RunSpec(study="benchmarks", ca=ca, level=a.mesh_level, t_end=a.strain,
                   t_avg_start=a.strain / 2, options=tuple(sorted(options.items())))


def series(folder, a, ca, scheme, steps):
    """D and S_xy of the capsule at every sample of a fixed-step run (None if it
    stopped)."""
    spec = fixed_step_spec(a, ca, scheme, steps)
    cmd = run_command(a.capsim, spec.capsim_options(threads=1), folder, "-q")
    if subprocess.run(cmd, check=False).returncode != 0:
        return None
    ts = read_timeseries(folder)
    assert len(ts["time"]) == a.samples + 1
    return np.stack([ts["D"][:, 0], ts["stresslet"][:, 0, 0, 1]])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--capsim", type=pathlib.Path, default=ROOT / "build" / "capsim")
    p.add_argument("--mesh-level", type=int, default=2)
    p.add_argument("--ca", default="0.05,0.2,0.6")
    p.add_argument("--schemes", default="imex,heun")
    p.add_argument("--strain", type=float, default=2.0)
    p.add_argument("--steps", default="5,10,20,40,80,160")
    p.add_argument("--reference", type=int, default=2560)
    p.add_argument("--reference-scheme", default="heun")
    p.add_argument("--samples", type=int, default=5,
                   help="compared at this many equally spaced strains (every step count "
                        "must be a multiple)")
    a = p.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for ca in (float(c) for c in a.ca.split(",")):
            ref = series(tmp / f"ref_{ca}", a, ca, a.reference_scheme, a.reference)
            for scheme in a.schemes.split(","):
                previous = None
                for steps in (int(n) for n in a.steps.split(",")):
                    got = series(tmp / f"{scheme}_{ca}_{steps}", a, ca, scheme, steps)
                    row = {"ca": ca, "scheme": scheme, "steps": steps,
                           "dt": a.strain / steps, "stable": got is not None}
                    if got is not None:
                        row["error_D"] = float(np.abs(got[0] - ref[0]).max())
                        row["error_Sxy"] = float(np.abs(got[1] - ref[1]).max())
                        if previous is not None:
                            for key in ("D", "Sxy"):
                                row[f"order_{key}"] = math.log2(
                                    previous[f"error_{key}"] / row[f"error_{key}"])
                    rows.append(row)
                    previous = row if got is not None else None
                    print(json.dumps(row), flush=True)
    result = {"mesh_level": a.mesh_level, "strain": a.strain,
              "reference_steps": a.reference, "rows": rows}
    (OUT / "time_order.json").write_text(json.dumps(result, indent=1))
    (OUT / "time_order.md").write_text(markdown_table(pd.DataFrame(rows), na_rep=""))
    print(f"wrote {OUT / 'time_order.json'}")


if __name__ == "__main__":
    main()

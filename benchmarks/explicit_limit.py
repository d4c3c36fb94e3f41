"""Where Heun's explicit step becomes unstable, as a multiple C of Ca h (the automatic
step is dt_safety Ca h / (1 + 4 eb / h^2)): a bisection on dt_safety, each trial one run
in simple shear that either reaches t_end or stops with a numerical failure (exit 3).

Usage: .venv/bin/python benchmarks/explicit_limit.py [--cases ...] [--capsim PATH]
           [--iterations 5]
Cases: dilute_L2, dilute_L3, dilute_L4 (one capsule, Ca 0.2), dilute_L2_Ca0.05,
dilute_L4_Ca0.05,
bending_L2 (eb 0.05), bending_L3 (eb 0.025), repulsion_L2 (phi 0.4, Ca 0.1, 8 capsules,
repulsion force 5). The limit found is bracketed by the largest stable and the smallest
unstable C; instability grows from round-off, so a run near the limit may survive a
short run that a longer one would not: the bracket is an upper estimate. Writes
results/benchmarks/explicit_limit.json and .md.
"""

import argparse
import json
import pathlib
import subprocess
import tempfile

import pandas as pd

from analysis.tables import markdown_table
from pipeline.command_line import run_command

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "results" / "benchmarks"
CASES = {
    "dilute_L2": {"mesh_level": 2, "ca": 0.2, "t_end": 20},
    "dilute_L2_Ca0.05": {"mesh_level": 2, "ca": 0.05, "t_end": 20},
    "dilute_L3": {"mesh_level": 3, "ca": 0.2, "t_end": 12},
    "dilute_L4": {"mesh_level": 4, "ca": 0.2, "t_end": 6},
    "dilute_L4_Ca0.05": {"mesh_level": 4, "ca": 0.05, "t_end": 6},
    "bending_L2": {"mesh_level": 2, "ca": 0.6, "membrane.bending": 0.05, "t_end": 20},
    "bending_L3": {"mesh_level": 3, "ca": 0.6, "membrane.bending": 0.025, "t_end": 12},
    "repulsion_L2": {"mesh_level": 2, "ca": 0.1, "phi": 0.4, "capsules": 8,
                     "suspension.repulsion_force": 5, "t_end": 10},
}


def stable(capsim, settings, safety, folder):
    options = {**settings, "dt_safety": safety, "t_avg_start": 0,
               "output.sample_interval": 0.5, "output.snapshot_interval": 0}
    cmd = run_command(capsim, options, folder, "-q")
    return subprocess.run(cmd, check=False, stderr=subprocess.DEVNULL).returncode == 0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", default=",".join(CASES))
    p.add_argument("--capsim", type=pathlib.Path, default=ROOT / "build" / "capsim")
    p.add_argument("--iterations", type=int, default=5)
    p.add_argument("--low", type=float, default=0.5)
    p.add_argument("--high", type=float, default=2.0)  # dt_safety allows (0, 2]
    a = p.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.cases.split(","):
            low, high = a.low, a.high
            for k in range(a.iterations):
                mid = 0.5 * (low + high)
                ok = stable(a.capsim, CASES[name], mid, pathlib.Path(tmp) / f"{name}_{k}")
                print(f"{name}: dt_safety {mid:.3f} {'stable' if ok else 'unstable'}",
                      flush=True)
                low, high = (mid, high) if ok else (low, mid)
            rows.append({"case": name, **CASES[name], "largest_stable": low,
                         "smallest_unstable": high})
    (OUT / "explicit_limit.json").write_text(json.dumps(rows, indent=1))
    (OUT / "explicit_limit.md").write_text(markdown_table(pd.DataFrame(rows), na_rep=""))
    print(f"wrote {OUT / 'explicit_limit.json'}")


if __name__ == "__main__":
    main()

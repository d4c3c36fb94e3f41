#!/usr/bin/env bash
# Speed benchmarks (never part of the tests). Writes JSON, Markdown tables and plots to
# results/benchmarks/. Run on an otherwise idle machine, after scripts/setup.sh.
#   bash benchmarks/run_benchmarks.sh [single|peak|ewald-accuracy|ewald-speed|precision|real-space-precision|xi|scaling|step|profile|all]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mkdir -p results/benchmarks
py=.venv/bin/python
what=${1:-all}
run() { [ "$what" = all ] || [ "$what" = "$1" ]; }
if run single; then # one capsule: seconds per RK2 step at levels 2-4, with its stages
  build/bench_single_capsule 5 > results/benchmarks/single_capsule.json
fi
if run peak; then # FMA peak, the real-space kernel's and the near corrections' rates
  build/peak_flops > results/benchmarks/peak_flops.json
  build/bench_screened_kernel > results/benchmarks/screened_kernel.json
  build/bench_near_corrections > results/benchmarks/near_corrections.json
fi
if run ewald-accuracy; then # error against tolerance, strains 0 and 0.5
  $py benchmarks/ewald_report.py accuracy --capsules 27 --mesh-level 2
fi
if run ewald-speed; then # seconds per evaluation against error
  $py benchmarks/ewald_report.py speed --capsules 27 --mesh-level 3
  $py benchmarks/ewald_report.py speed --capsules 100 --mesh-level 3
fi
if run precision; then # Spectral Ewald's grids in double and single precision
  $py benchmarks/ewald_report.py precision --capsules 27 --mesh-level 3
fi
if run real-space-precision; then # the real-space sum in double and single precision
  $py benchmarks/ewald_report.py real-space-precision --capsules 27 --mesh-level 3
fi
if run xi; then # Spectral Ewald's automatic xi against others, at the workflow's tolerances
  # (ewald.tolerance auto at levels 3 and 4: the runs' summaries)
  $py benchmarks/ewald_report.py xi --capsules 27 --mesh-level 3 --tolerance 1.88e-3
  $py benchmarks/ewald_report.py xi --capsules 27 --mesh-level 4 --tolerance 6.0e-4
fi
if run scaling; then # 1e4 to 1e6 sources
  $py benchmarks/ewald_report.py scaling --mesh-level 3
fi
if run step; then # seconds per RK2 step of a run, with and without patches
  $py benchmarks/ewald_report.py step --capsules 27 --mesh-level 3
  $py benchmarks/ewald_report.py step --capsules 100 --mesh-level 3
fi
if run profile; then # every stage of a step in situ, levels 3 and 4, against its bound
  $py benchmarks/step_profile.py --out results/benchmarks/step_profile.json
fi
echo "benchmarks: results in results/benchmarks/"

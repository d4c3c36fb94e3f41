#!/usr/bin/env bash
# Speed benchmarks (never part of the tests). Writes JSON to results/benchmarks/.
#   bench_single_capsule: seconds per RK2 step for one capsule at mesh levels 2-4, split
#   into membrane forces, quadrature set-up, the dense far sum and near corrections.
# Usage: bash benchmarks/run_benchmarks.sh [REPEATS]   (after scripts/setup.sh)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mkdir -p results/benchmarks
out=results/benchmarks/single_capsule.json
build/bench_single_capsule "${1:-5}" > "$out"
echo "benchmarks: wrote $out"
cat "$out"

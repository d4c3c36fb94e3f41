#!/usr/bin/env bash
# Runs every test: sets up and builds (scripts/setup.sh), then the CUDA backend's self-test
# on the CPU (the device code in a host-emulation build, build-emulate/), the C++ suite
# under the address and undefined-behaviour sanitizers (build-sanitize/), the C++ suite
# with ctest, the SLURM profile on a one-node SLURM started on this machine
# (tests/python/test_slurm.py, as root) and the rest of the Python suite with pytest. All
# five always run; pytest's summary is the last line. Exits non-zero if setup or any of
# them failed.
#
# Environment: CAPSIM_JOBS=N (parallel build and test jobs, default 2),
#              CAPSIM_TEST_TIMEOUT=S (default per-test limit in seconds for ctest, 900).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

JOBS="${CAPSIM_JOBS:-2}"

# Configures a second build folder DIR (Release, no benchmarks, Ninja when present) with
# the extra CMake arguments given; the report goes to DIR/configure.log.
configure_variant() {
  local dir=$1
  shift
  local args=(-S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCAPSIM_BENCHMARKS=OFF
    "-DCAPSIM_NATIVE=${CAPSIM_NATIVE:-OFF}" "$@")
  if [ ! -f "$dir/CMakeCache.txt" ] && command -v ninja >/dev/null 2>&1; then
    args+=(-G Ninja)
  fi
  mkdir -p "$dir"
  cmake "${args[@]}" >"$dir/configure.log" 2>&1 || {
    cat "$dir/configure.log" >&2
    return 1
  }
}

# The CUDA backend built with CAPSIM_CUDA=EMULATE (kernels run as loops on the CPU,
# docs/gpu.md): only the capsim executable, then its comparison with the CPU backend.
emulated_device_selftest() {
  local dir=build-emulate
  configure_variant "$dir" -DCAPSIM_CUDA=EMULATE -DCAPSIM_TESTS=OFF || return 1
  cmake --build "$dir" --target capsim --parallel "$JOBS" || return 1
  "$dir/capsim" selftest --backend cuda
}

# The C++ suite built with AddressSanitizer and UndefinedBehaviorSanitizer (CAPSIM_SANITIZE,
# build-sanitize/, no CUDA, no benchmarks); any report fails its test. The slowest tests
# (about 200 s each under the sanitizers; the capsules at lambda != 1 to steady state, the
# drops against Taylor and the periodic deflated solve, hundreds of GMRES solves or long
# Ewald sums) run in the plain suite only; the IMEX, relaxation, second-kind, periodic
# double-layer and drop paths they take are covered by faster tests here. Built at -O1 (the level the
# sanitizers' authors advise) as a unity build: about 200 s instead of 470 s at -O3 file by
# file on 2 cores, for the same test time.
sanitized_suite() {
  local dir=build-sanitize
  configure_variant "$dir" -DCAPSIM_SANITIZE=ON -DCAPSIM_CUDA=OFF -DCMAKE_UNITY_BUILD=ON \
    "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" || return 1
  cmake --build "$dir" --parallel "$JOBS" >"$dir/build.log" 2>&1 || {
    tail -50 "$dir/build.log" >&2
    return 1
  }
  LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp" \
    ctest_suite "$dir" -E "relaxes to a sphere, energy decreasing|converges at second order|capsule at lambda|drop: .*Taylor|deflated solve is the equation"
}

# The C++ suite of build folder $1 (extra ctest arguments after it). --no-tests=error: an
# empty suite (e.g. a broken test discovery) is a failure, not a pass. The tests run
# $JOBS at a time, each with as many OpenMP threads as cores: with threads that sleep
# rather than spin while they wait (OMP_WAIT_POLICY=passive), four single-capsule IMEX
# tests took 22 s instead of 124 s on 2 cores that another two-thread run shared. Their
# results do not change.
ctest_suite() {
  local dir=$1
  shift
  OMP_WAIT_POLICY=passive ctest --test-dir "$dir" --output-on-failure -j "$JOBS" --no-tests=error \
    --timeout "${CAPSIM_TEST_TIMEOUT:-900}" "$@"
}

# Runs one part (the command after its name), timed; a failure is reported and returned,
# and the caller goes on with the other parts.
run_part() {
  local name=$1 rc=0
  shift
  echo "test: $name"
  SECONDS=0
  "$@" || rc=$?
  echo "test: $name took ${SECONDS} s"
  if [ "$rc" -ne 0 ]; then
    echo "test: $name FAILED (exit $rc); running the other parts anyway"
  fi
  return "$rc"
}

# The SLURM profile against a real one-node SLURM (slurmctld, slurmd, munge) that the test
# starts on this machine and stops again: a part of its own, so that its time shows. It
# fails, saying why, where the daemons cannot start (not root, not installed, a slurm.conf
# of the machine's own).
slurm_suite() {
  .venv/bin/python -m pytest tests/python/test_slurm.py -v -s
}

bash scripts/setup.sh

emulate_rc=0
run_part "CUDA backend emulated on the CPU (build-emulate/, capsim selftest --backend cuda)" \
  emulated_device_selftest || emulate_rc=$?
sanitize_rc=0
run_part "C++ suite under AddressSanitizer and UndefinedBehaviorSanitizer (build-sanitize/)" \
  sanitized_suite || sanitize_rc=$?
ctest_rc=0
run_part "C++ suite (ctest)" ctest_suite build || ctest_rc=$?
slurm_rc=0
run_part "SLURM profile on a one-node SLURM (tests/python/test_slurm.py)" slurm_suite ||
  slurm_rc=$?

echo "test: Python suite (pytest)"
pytest_rc=0
# Exit code 5 (no tests collected) counts as a failure like any other non-zero code.
.venv/bin/python -m pytest tests/python -q --ignore=tests/python/test_slurm.py || pytest_rc=$?

# Nothing is printed after this point, so pytest's summary stays the last line.
if [ "$ctest_rc" -ne 0 ]; then exit "$ctest_rc"; fi
if [ "$emulate_rc" -ne 0 ]; then exit "$emulate_rc"; fi
if [ "$sanitize_rc" -ne 0 ]; then exit "$sanitize_rc"; fi
if [ "$slurm_rc" -ne 0 ]; then exit "$slurm_rc"; fi
exit "$pytest_rc"

#!/usr/bin/env bash
# Runs every test: sets up and builds (scripts/setup.sh); then, in the background at the
# lowest priority, builds the C++ suite with the address and undefined-behaviour
# sanitizers and the CUDA backend in host emulation (build-sanitize/) and runs the CUDA
# backend's self-test on the CPU with that build's capsim and the C++ suite under the
# sanitizers; meanwhile the Python suite's cluster tests (the SLURM profile on a one-node
# SLURM started on this machine, as root) and the C++ suite with ctest; last the rest of
# the Python suite with pytest. All parts always run; pytest's summary is the last line.
# Exits non-zero if setup or any of them failed.
#
# Environment: CAPSIM_JOBS=N (parallel build and test jobs, default 2),
#              CAPSIM_TEST_TIMEOUT=S (default per-test limit in seconds for ctest, 900).
# (`scripts/test.sh --sanitized-part` is how it starts the sanitized part in the
# background; not meant to be called alone.)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

JOBS="${CAPSIM_JOBS:-2}"
# LeakSanitizer's known reports outside the project (tests/sanitizers/lsan.supp), for
# every run of the sanitized build: its self-test, its suite and pytest's emulated device.
export LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp"

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

# The C++ suite and capsim built with AddressSanitizer and UndefinedBehaviorSanitizer
# (CAPSIM_SANITIZE, build-sanitize/, no benchmarks) and the CUDA backend in host emulation
# (CAPSIM_CUDA=EMULATE: its kernels run as loops on the CPU, docs/gpu.md), so that the
# device code runs under the sanitizers too and one build serves both parts (a build of
# its own for the emulation cost about 4 minutes of CI). Built at -O1 (the level the
# sanitizers' authors advise) as a unity build: about 200 s instead of 470 s at -O3 file
# by file on 2 cores, for the same test time.
sanitized_build() {
  local dir=build-sanitize
  configure_variant "$dir" -DCAPSIM_SANITIZE=ON -DCAPSIM_CUDA=EMULATE -DCMAKE_UNITY_BUILD=ON \
    "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" || return 1
  cmake --build "$dir" --parallel "$JOBS" >"$dir/build.log" 2>&1 || {
    tail -50 "$dir/build.log" >&2
    return 1
  }
}

# The CUDA backend's device code against the CPU backend (capsim selftest), emulated.
emulated_device_selftest() {
  build-sanitize/capsim selftest --backend cuda
}

# The C++ suite under the sanitizers; any report fails its test. The slowest tests (about
# 200 s each under the sanitizers; the capsules at lambda != 1 to steady state, the drops
# against Taylor and the periodic deflated solve, hundreds of GMRES solves or long Ewald
# sums) run in the plain suite only; the IMEX, relaxation, second-kind, periodic
# double-layer and drop paths they take are covered by faster tests here.
sanitized_suite() {
  ctest_suite build-sanitize -E "relaxes to a sphere, energy decreasing|converges at second order|capsule at lambda|drop: .*Taylor|deflated solve is the equation"
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

# The sanitized part: its build, then the emulated self-test and the suite where it
# built; writes their exit codes (self-test, suite) to the file $1.
sanitized_part() {
  local build_rc=0 emulate_rc sanitize_rc
  run_part "build-sanitize/ (AddressSanitizer, UndefinedBehaviorSanitizer, CUDA backend emulated)" \
    sanitized_build || build_rc=$?
  emulate_rc=$build_rc
  sanitize_rc=$build_rc
  if [ "$build_rc" -eq 0 ]; then
    run_part "CUDA backend emulated on the CPU (build-sanitize/capsim selftest --backend cuda)" \
      emulated_device_selftest || emulate_rc=$?
    run_part "C++ suite under AddressSanitizer and UndefinedBehaviorSanitizer (build-sanitize/)" \
      sanitized_suite || sanitize_rc=$?
  fi
  echo "$emulate_rc $sanitize_rc" >"$1"
}

if [ "${1:-}" = "--sanitized-part" ]; then
  # Its own scheduling group at the lowest weight, where the kernel groups processes by
  # setsid (autogroup, as root): the lower priority below then holds against the cluster
  # tests' processes in other groups too.
  echo 19 >/proc/self/autogroup 2>/dev/null || true
  sanitized_part "$2"
  exit 0
fi

bash scripts/setup.sh

# The sanitized part runs in the background from here, beside the cluster tests, which
# mostly wait for SLURM (on 2 cores they kept 63 % of them busy: docs/reliability.md), at
# the lowest priority: SCHED_IDLE and niceness 19, under setsid in a group of its own. It
# takes the cores the others leave, so the SLURM jobs and the SLURM workflow, itself at
# niceness 19, keep theirs. Its report is printed after the plain C++ suite; nothing
# before reads build-sanitize/.
sanitized_log=$(mktemp)
sanitized_rcs=$(mktemp)
echo "1 1" >"$sanitized_rcs"
setsid -w nice -n 19 chrt --idle 0 bash "$ROOT/scripts/test.sh" --sanitized-part "$sanitized_rcs" \
  >"$sanitized_log" 2>&1 &
sanitized_pid=$!
# Interrupted, the script takes it down too (the process group setsid gave it).
trap 'kill -- -"$sanitized_pid" 2>/dev/null || true' EXIT

# The cluster tests (test_slurm.py, and test_workflow_ci.py, whose local ci workflow
# test_slurm.py compares with): the SLURM profile on a one-node SLURM that test_slurm.py
# starts on this machine (as root) and stops again; they fail, saying why, where the
# daemons cannot start (not root, not installed, a slurm.conf of the machine's own). Exit
# code 5 (no tests collected) counts as a failure like any other non-zero code. Nothing
# but the sanitized part at its lowest priority runs beside them: their SLURM workflow
# runs at niceness 19 (test_slurm.py), and beside the C++ suites at niceness 0 the SLURM
# plugin did not read MinJobAge within its 10 s (`scontrol show config`), fell back to
# sacct, which has no database here, and the workflow hung until the test's 900 s limit
# (docs/reliability.md).
CLUSTER_TESTS=(tests/python/test_slurm.py tests/python/test_workflow_ci.py)
cluster_rc=0
run_part "Python cluster tests (${CLUSTER_TESTS[*]})" \
  .venv/bin/python -m pytest "${CLUSTER_TESTS[@]}" -q --durations=5 || cluster_rc=$?
ctest_rc=0
run_part "C++ suite (ctest)" ctest_suite build || ctest_rc=$?
wait "$sanitized_pid" || true
cat "$sanitized_log"
read -r emulate_rc sanitize_rc <"$sanitized_rcs"
rm -f "$sanitized_log" "$sanitized_rcs"
# The rest of the Python suite on $JOBS workers (pytest-xdist; --dist loadfile: a file's
# tests on one worker, so its module fixtures are made once); the slowest tests' times
# are listed before the summary.
echo "test: Python suite (pytest, the cluster tests above excepted)"
pytest_rc=0
.venv/bin/python -m pytest tests/python -q --durations=12 -n "$JOBS" --dist loadfile \
  "${CLUSTER_TESTS[@]/#/--ignore=}" || pytest_rc=$?

# Nothing is printed after this point, so pytest's summary stays the last line.
if [ "$ctest_rc" -ne 0 ]; then exit "$ctest_rc"; fi
if [ "$emulate_rc" -ne 0 ]; then exit "$emulate_rc"; fi
if [ "$sanitize_rc" -ne 0 ]; then exit "$sanitize_rc"; fi
if [ "$cluster_rc" -ne 0 ]; then exit "$cluster_rc"; fi
exit "$pytest_rc"

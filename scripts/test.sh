#!/usr/bin/env bash
# Runs every test: sets up and builds (scripts/setup.sh), then the C++ suite with ctest and
# the Python suite with pytest. Both suites always run, so both summaries are printed;
# pytest's summary is the last line. Exits non-zero if setup or either suite failed.
#
# Environment: CAPSIM_JOBS=N (parallel build and test jobs, default 2),
#              CAPSIM_TEST_TIMEOUT=S (default per-test limit in seconds for ctest, 900).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

JOBS="${CAPSIM_JOBS:-2}"

bash scripts/setup.sh

echo "test: C++ suite (ctest)"
ctest_rc=0
# --no-tests=error: an empty suite (e.g. a broken test discovery) is a failure, not a pass.
ctest --test-dir build --output-on-failure -j "$JOBS" --no-tests=error \
  --timeout "${CAPSIM_TEST_TIMEOUT:-900}" || ctest_rc=$?
if [ "$ctest_rc" -ne 0 ]; then
  echo "test: ctest FAILED (exit $ctest_rc); running the Python suite anyway"
fi

echo "test: Python suite (pytest)"
pytest_rc=0
# Exit code 5 (no tests collected) counts as a failure like any other non-zero code.
.venv/bin/python -m pytest tests/python -q || pytest_rc=$?

# Nothing is printed after this point, so pytest's summary stays the last line.
if [ "$ctest_rc" -ne 0 ]; then exit "$ctest_rc"; fi
exit "$pytest_rc"

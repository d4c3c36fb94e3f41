#!/usr/bin/env bash
# Installs what the project needs and builds it. Safe to run again: every step checks first
# and skips itself when there is nothing to do.
#
#   1. Debian packages (compilers, CMake, Ninja, Eigen, HDF5, FFTW, yaml-cpp, CLI11, Catch2,
#      Thrust, SLURM and munge for the one-node SLURM test, and python3-venv where
#      `python3 -m venv` would not work): installed only if missing.
#   2. .venv/ with the pinned requirements.txt and the analysis package (pyproject.toml,
#      editable: `pip install -e .`): made again whenever either file changes.
#   3. build/: CMake Release build of the solver (with the CUDA backend where nvcc is
#      found), its tests and benchmarks.
#
# Usage: bash scripts/setup.sh [--no-build]
# Environment:
#   CAPSIM_JOBS=N      parallel build jobs (default 2)
#   CAPSIM_NATIVE=ON   compile with -march=native (default OFF; fast but tied to this CPU)
#   CAPSIM_CUDA=X      CUDA backend: AUTO (default; built when nvcc is found), ON, OFF,
#                      EMULATE (the device code run on the CPU; test.sh builds it apart)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

JOBS="${CAPSIM_JOBS:-2}"
BUILD_DIR=build
VENV=.venv
STAMP="$VENV/requirements.sha256"
# libthrust-dev: the Thrust headers for the CPU emulation of the CUDA backend (test.sh).
# munge slurmctld slurmd slurm-client: the one-node SLURM that tests/python/test_slurm.py
# starts (with its own munge key and slurm.conf) and stops again, to run the SLURM profile
# against; the system's slurmctld and slurmd services start only where an
# /etc/slurm/slurm.conf exists, which the installation does not write.
APT_PACKAGES=(build-essential cmake ninja-build pkg-config libeigen3-dev libhdf5-dev
  libfftw3-dev libyaml-cpp-dev libcli11-dev catch2 libthrust-dev
  munge slurmctld slurmd slurm-client)

log() { printf 'setup: %s\n' "$*"; }
die() { printf 'setup: error: %s\n' "$*" >&2; exit 1; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then
    "$@"
  elif command -v sudo >/dev/null 2>&1; then
    sudo "$@"
  else
    die "not root and no sudo: cannot run '$*'"
  fi
}

is_installed() { dpkg -s "$1" 2>/dev/null | grep -q '^Status: install ok installed'; }

# python3 on PATH can make a venv with pip (Debian's own python3 needs python3-venv for that).
python_can_make_venv() { command -v python3 >/dev/null 2>&1 && python3 -c 'import venv, ensurepip' 2>/dev/null; }

install_apt_packages() {
  local wanted=("${APT_PACKAGES[@]}") missing=() pkg
  if ! python_can_make_venv; then
    wanted+=(python3 python3-venv)
  fi
  for pkg in "${wanted[@]}"; do
    is_installed "$pkg" || missing+=("$pkg")
  done
  if [ "${#missing[@]}" -eq 0 ]; then
    log "system packages present"
    return
  fi
  log "installing system packages: ${missing[*]}"
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
}

check_python() {
  python_can_make_venv || die "python3 cannot create virtual environments (install python3-venv)"
  python3 -c 'import sys; sys.exit(sys.version_info < (3, 11))' ||
    die "python3 is $(python3 -V 2>&1); the pinned requirements need Python >= 3.11"
}

setup_venv() {
  local want
  # Both files decide what goes into the venv: a change to either redoes it.
  want="$(cat requirements.txt pyproject.toml | sha256sum | cut -d' ' -f1)"
  if [ -x "$VENV/bin/python" ] && "$VENV/bin/python" -c 'import sys' 2>/dev/null &&
    [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$want" ]; then
    log "python environment up to date ($VENV)"
    return
  fi
  check_python
  log "creating $VENV with $(python3 -V 2>&1), installing requirements.txt and the analysis package"
  rm -rf "$VENV"
  python3 -m venv "$VENV"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-input \
    -r requirements.txt
  # Editable: the workflow and the figure scripts import the checkout's analysis/ as it is.
  # --no-deps: the versions are those just pinned by requirements.txt.
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-input \
    --no-deps -e .
  echo "$want" >"$STAMP"  # written last: an interrupted install is redone next time
  log "python environment ready"
}

configure_and_build() {
  local args=(-S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
    "-DCAPSIM_NATIVE=${CAPSIM_NATIVE:-OFF}" "-DCAPSIM_CUDA=${CAPSIM_CUDA:-AUTO}")
  # Choose the generator only for a fresh build directory: CMake refuses to switch it.
  if [ ! -f "$BUILD_DIR/CMakeCache.txt" ] && command -v ninja >/dev/null 2>&1; then
    args+=(-G Ninja)
  fi
  log "configuring $BUILD_DIR/ (Release, CAPSIM_NATIVE=${CAPSIM_NATIVE:-OFF}, CAPSIM_CUDA=${CAPSIM_CUDA:-AUTO})"
  mkdir -p "$BUILD_DIR"
  # The configure report is long; keep it in a file and show it only when it failed.
  cmake "${args[@]}" >"$BUILD_DIR/configure.log" 2>&1 || {
    cat "$BUILD_DIR/configure.log" >&2
    die "CMake configure failed (log: $BUILD_DIR/configure.log)"
  }
  grep -h '^-- capsim: CUDA backend' "$BUILD_DIR/configure.log" | sed 's/^-- /setup: /' || true
  log "building with $JOBS jobs"
  cmake --build "$BUILD_DIR" --parallel "$JOBS" || die "build failed"
  log "build done"
}

main() {
  local build=1
  for arg in "$@"; do
    case "$arg" in
      --no-build) build=0 ;;
      -h | --help) sed -n '2,/^set /{/^#/p}' "$0"; exit 0 ;;
      *) die "unknown argument '$arg' (try --help)" ;;
    esac
  done
  install_apt_packages
  setup_venv
  if [ "$build" -eq 1 ]; then
    configure_and_build
  else
    log "skipping the build (--no-build)"
  fi
  log "done"
}

main "$@"

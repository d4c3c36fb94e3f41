#!/usr/bin/env bash
# The project's main command. Sets up and builds (scripts/setup.sh), then runs the
# reproduction workflow with the default, laptop-sized configuration (config/config.yaml):
# `snakemake --cores N` in the project's virtual environment. Runs that have finished are
# not repeated; a run that was stopped resumes from its checkpoint. Extra arguments go to
# snakemake (e.g. `-n` for a dry run, `--configfile config/other.yaml`).
#
# Environment: the same as scripts/setup.sh (CAPSIM_JOBS = cores, default 2; CAPSIM_NATIVE).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

bash scripts/setup.sh
echo "reproduce: snakemake --cores ${CAPSIM_JOBS:-2} $*"
.venv/bin/snakemake --cores "${CAPSIM_JOBS:-2}" "$@"
if [ -f results/dilute/table.md ]; then
  echo "reproduce: dilute-limit table (results/dilute/table.md):"
  cat results/dilute/table.md
fi

#!/usr/bin/env bash
# The project's main command. Sets up and builds (scripts/setup.sh), then runs the
# reproduction workflow: `snakemake --cores N` in the project's virtual environment.
#
# Without arguments it regenerates the quantitative reproduction (config/quantitative.yaml:
# figures 1-12, Table 1, the comparison with the paper and its check) from the results
# archive (archive/quantitative), which holds every run: minutes, where computing them
# takes 8-9 hours. With arguments, they go to snakemake with the default, laptop-sized
# configuration (config/config.yaml), computed from scratch (`all check`), unless they
# name another (`--configfile config/other.yaml`; `-n` for a dry run). Either way runs
# that have finished are not repeated; a run that was stopped resumes from its checkpoint.
#
# Environment: the same as scripts/setup.sh (CAPSIM_JOBS = cores, default 2; CAPSIM_NATIVE).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

bash scripts/setup.sh
if [ $# -eq 0 ]; then
  set -- all check --configfile config/quantitative.yaml
fi
echo "reproduce: snakemake --cores ${CAPSIM_JOBS:-2} $*"
.venv/bin/snakemake --cores "${CAPSIM_JOBS:-2}" "$@"
if [ -f results/dilute/table.md ]; then
  echo "reproduce: dilute-limit table (results/dilute/table.md):"
  cat results/dilute/table.md
fi

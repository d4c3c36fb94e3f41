#!/usr/bin/env bash
# The project's main command. Sets up and builds (scripts/setup.sh), then runs what the
# solver can do today: one capsule in the dilute limit (config/dilute_example.yaml), and
# prints its summary. A run that was stopped continues from its last checkpoint; a run that
# has finished is not repeated (delete results/dilute_example/ to run it again).
#
# Environment: the same as scripts/setup.sh (CAPSIM_JOBS, CAPSIM_NATIVE).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

CONFIG=config/dilute_example.yaml
RUN_DIR=results/dilute_example

log() { printf 'reproduce: %s\n' "$*"; }

bash scripts/setup.sh

# The build puts the executable at build/capsim.
CAPSIM=""
for candidate in build/capsim; do
  if [ -x "$candidate" ]; then CAPSIM="$candidate"; break; fi
done
if [ -z "$CAPSIM" ]; then
  echo "reproduce: error: no capsim executable under build/ (did the build succeed?)" >&2
  exit 1
fi

if [ -f "$RUN_DIR/summary.json" ]; then
  log "$RUN_DIR has finished already (delete it to run again)"
elif [ -f "$RUN_DIR/checkpoint.h5" ]; then
  log "resuming $RUN_DIR from its checkpoint"
  "$CAPSIM" run --resume "$RUN_DIR"
else
  log "running $CONFIG into $RUN_DIR"
  mkdir -p results
  "$CAPSIM" run "$CONFIG" -o "$RUN_DIR"
fi

log "summary ($RUN_DIR/summary.json):"
cat "$RUN_DIR/summary.json"
echo

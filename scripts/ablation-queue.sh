#!/usr/bin/env bash
# Runs a queue of ablation sweeps one after another (results/ablation-level2/README.md):
# each entry is TASK:PLANNER:VARIANT, trained from configs/ablation-level2/VARIANT with 5 seeds
# into OUT_DIR/TASK-PLANNER/VARIANT. Started again with the same arguments it skips finished
# runs and resumes the others.
# Usage: [JOBS=2] scripts/ablation-queue.sh CMBRL_BINARY OUT_DIR ENTRY...
# Two queues side by side, one CPU each, keep both CPUs busy when a sweep's last run is alone:
#   taskset -c 0 env JOBS=1 scripts/ablation-queue.sh ... & taskset -c 1 env JOBS=1 ...
set -euo pipefail
cd "$(dirname "$0")/.."
cmbrl=$1
out=$2
shift 2
for entry in "$@"; do
  IFS=: read -r task planner variant <<<"$entry"
  "$cmbrl" sweep --config-dir "configs/ablation-level2/$variant" --tasks "$task" \
    --planners "$planner" --seeds 0 1 2 3 4 --jobs "${JOBS:-2}" --out "$out/$task-$planner/$variant"
done

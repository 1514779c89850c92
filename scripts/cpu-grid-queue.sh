#!/usr/bin/env bash
# The runs the CPU grid (configs/cpu, results/cpu-grid) still lacks, in the order that answers
# issue 12 soonest. Every cell has 3 seeds (5 for the level-2 RCE cells); three cells stand in
# results/cpu-grid/first-25-runs/table-1.csv because their runs' logs were lost with an earlier
# machine, so they have no curves or first epochs in the report. This makes them again with
# logs. PointGoal1 RCE and PointGoal2 RCE were made again so on 2026-11-25 (in the report's
# run-logs). A cell made from runs replaces such a
# cell whole, so give the report a cell's runs only once all its seeds are finished.
# Started again with the same arguments it skips finished runs and resumes the others. Then:
#   cmbrl report results/cpu-grid OUT_DIR --earlier-table \
#       results/cpu-grid/first-25-runs/table-1.csv --out results/cpu-grid --window 3000 --complete
# Usage: [JOBS=1] scripts/cpu-grid-queue.sh CMBRL_BINARY OUT_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
cmbrl=$1
out=$2

sweep() {
  "$cmbrl" sweep --config-dir configs/cpu --out "$out" --jobs "${JOBS:-1}" "$@"
}
sweep --tasks CarGoal1 --planners rce cem random --seeds 0 1 2

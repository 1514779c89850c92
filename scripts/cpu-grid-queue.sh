#!/usr/bin/env bash
# The runs the CPU grid (configs/cpu, results/cpu-grid) still lacks, in the order that answers
# issue 12 soonest: every cell to 3 seeds. The committed report holds the logs of the runs made
# so far (results/cpu-grid/run-logs/), and the cells whose logs were lost with an earlier
# machine stand in results/cpu-grid/first-25-runs/table-1.csv; a cell made from runs replaces
# such a cell whole, so PointGoal2 CEM is made again with all three seeds.
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
# Seeds 0 and 1 so far (2026-11-25): both in the report's run-logs.
sweep --tasks CarGoal2 --planners random --seeds 2
# Seeds 0 and 1 so far, in the report's run-logs.
sweep --tasks PointGoal2 --planners cem --seeds 2

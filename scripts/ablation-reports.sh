#!/usr/bin/env bash
# Reports of every finished ablation sweep under RUNS_DIR (scripts/ablation-queue.sh's layout,
# RUNS_DIR/<task>-<method>/<variant>) into OUT_DIR with the same layout, over WINDOW agent steps,
# then their common table (scripts/ablation-table.py) as OUT_DIR/table.md.
# Usage: scripts/ablation-reports.sh CMBRL_BINARY RUNS_DIR OUT_DIR [WINDOW]
set -euo pipefail
cd "$(dirname "$0")/.."
cmbrl=$1
runs=$2
out=$3
window=${4:-2000}
for sweep in "$runs"/*/*/; do
  sweep=${sweep%/}
  cell=$(basename "$(dirname "$sweep")")
  variant=$(basename "$sweep")
  # Only sweeps whose five runs all reached the window.
  finished=0
  for progress in "$sweep"/runs/*/progress.csv; do
    [ -f "$progress" ] || continue
    last=$(tail -1 "$progress" | cut -d, -f5)
    if [[ "$last" =~ ^[0-9]+$ ]] && [ "$last" -ge "$window" ]; then finished=$((finished + 1)); fi
  done
  if [ "$finished" -lt 5 ]; then
    echo "skipping $cell/$variant: $finished of 5 runs reached $window steps" >&2
    continue
  fi
  "$cmbrl" report "$sweep" --out "$out/$cell/$variant" --window "$window" > /dev/null
  rm -f "$out/$cell/$variant"/*.svg
done
python3 scripts/ablation-table.py "$out" > "$out/table.md"

#!/usr/bin/env bash
# The CPU grid (configs/cpu, results/cpu-grid) in the order that answers issue 12 soonest: the
# level-2 RCE cells with 5 seeds and the Car baselines, seed by seed, then the rest with 3 seeds.
# Started again with the same arguments it skips finished runs and resumes the others.
#
# The ablation variant 'combined' is the CPU preset at 2000 steps: its finished runs (in
# ABLATION_DIR/<Task>-rce/combined/runs, scripts/ablation-queue.sh's layout) are copied in and
# continued to 3000 steps instead of being trained again (`cmbrl train --resume --steps`, which
# gives the rows of a run started with 3000).
# Usage: [JOBS=1] scripts/cpu-grid-queue.sh CMBRL_BINARY OUT_DIR [ABLATION_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
cmbrl=$1
out=$2
ablation=${3:-}

if [ -n "$ablation" ]; then
  mkdir -p "$out/runs"
  for run in "$ablation"/*-rce/combined/runs/*/; do
    [ -f "$run/config.yaml" ] || continue
    name=$(basename "$run")
    [ -e "$out/runs/$name" ] && continue
    # Only a run that reached its 2000 steps: an unfinished one simply trains in the grid.
    last=$(tail -1 "$run/progress.csv" | cut -d, -f5)
    if [[ "$last" =~ ^[0-9]+$ ]] && [ "$last" -ge 2000 ]; then
      cp -a "${run%/}" "$out/runs/$name"
      rm -f "$out/runs/$name/lock"
      "$cmbrl" train --resume "$out/runs/$name" --steps 3000 > /dev/null
    fi
  done
fi

sweep() {
  "$cmbrl" sweep --config-dir configs/cpu --out "$out" --jobs "${JOBS:-1}" "$@"
}
sweep --tasks PointGoal2 --planners rce --seeds 0 1 2 3 4
# The Car's two gaps side by side, a seed of each at a time: level-2 RCE and the baselines.
for seed in 0 1 2; do
  sweep --tasks CarGoal2 --planners rce --seeds "$seed"
  sweep --tasks CarGoal1 --planners cem random --seeds "$seed"
done
sweep --tasks CarGoal2 --planners rce --seeds 3 4
sweep --tasks PointGoal1 CarGoal1 --planners rce --seeds 0 1 2
sweep --tasks PointGoal2 CarGoal2 --planners cem random --seeds 0 1 2
sweep --tasks PointGoal1 --planners cem random --seeds 0 1 2

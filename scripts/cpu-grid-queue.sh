#!/usr/bin/env bash
# The CPU grid (configs/cpu, results/cpu-grid) in the order that answers issue 12 soonest: the
# level-2 RCE cells with 5 seeds, then the rest with 3 seeds.
# Started again with the same arguments it skips finished runs and resumes the others.
#
# The ablation variant 'combined' on PointGoal2 RCE is the CPU preset at 2000 steps: its
# finished runs (in ABLATION_DIR/PointGoal2-rce/combined/runs, scripts/ablation-queue.sh's
# layout) are copied in and continued to 3000 steps instead of being trained again (`cmbrl train
# --resume --steps`, which gives the rows of a run started with 3000). Its Car cells are not:
# they predict the absolute state, as the Car presets no longer do (ConfigTest,
# TheCombinedAblationIsTheCpuPresetAtTwoThousandSteps).
# Usage: [JOBS=1] scripts/cpu-grid-queue.sh CMBRL_BINARY OUT_DIR [ABLATION_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
cmbrl=$1
out=$2
ablation=${3:-}

if [ -n "$ablation" ]; then
  mkdir -p "$out/runs"
  for run in "$ablation"/PointGoal2-rce/combined/runs/*/; do
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
sweep --tasks PointGoal1 --planners rce --seeds 0 1 2
# The Car presets predict the change of state since 2026-11-24 (configs/cpu/cargoal*.yaml): the
# Car's RCE cells first, then the baselines. CarGoal1's CEM and random runs are the ablation
# 'delta' runs (the same configuration, copied in), so the sweep skips them once they are here.
sweep --tasks CarGoal1 --planners rce --seeds 0 1 2
sweep --tasks CarGoal2 --planners rce --seeds 0 1 2 3 4
sweep --tasks PointGoal2 CarGoal2 --planners cem random --seeds 0 1 2
sweep --tasks PointGoal1 --planners cem random --seeds 0 1 2
sweep --tasks CarGoal1 --planners cem random --seeds 0 1 2

#!/usr/bin/env bash
# The level-2 ablations of results/ablation-level2/ (issue 12): one sweep per variant in
# configs/ablation-level2/, 5 seeds, the 2000-step screening window, then their reports.
# Usage: scripts/ablation-level2.sh CMBRL_BINARY OUT_DIR TASK [VARIANT...]
# Started again with the same arguments it skips finished runs and resumes the others.
set -euo pipefail
cd "$(dirname "$0")/.."
cmbrl=$1
out=$2
task=$3
shift 3
variants=("$@")
if [ "${#variants[@]}" -eq 0 ]; then
  variants=(grid faithful population dynamics classifier min-child-weight bonus labels)
fi
for variant in "${variants[@]}"; do
  "$cmbrl" sweep --config-dir "configs/ablation-level2/$variant" --tasks "$task" --planners rce \
    --seeds 0 1 2 3 4 --jobs 2 --out "$out/$variant"
done

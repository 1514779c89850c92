#!/usr/bin/env bash
# kill -9 a training run at an arbitrary moment of its life (once its directory holds a run),
# resume it, and compare its progress.csv with an uninterrupted run's (the wall-clock columns
# Time and MsPerPlan aside).
# Usage: kill_resume_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1 config=$2 work=$3
rm -rf "$work" && mkdir -p "$work"

"$cmbrl" train --config "$config" --steps 1200 --out "$work/whole" > /dev/null
for delay in 0.3 1.5; do
  run="$work/killed-$delay"
  "$cmbrl" train --config "$config" --steps 1200 --out "$run" > /dev/null &
  pid=$!
  # The run exists once config.yaml is in place (the program may still be loading LibTorch).
  for _ in $(seq 300); do [ -f "$run/config.yaml" ] && break; sleep 0.1; done
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" 2> /dev/null || true
  "$cmbrl" train --resume "$run" > /dev/null
  if ! diff <(deterministic_rows "$work/whole/progress.csv") \
            <(deterministic_rows "$run/progress.csv"); then
    echo "FAILED: rows differ after kill -9 at ${delay}s and resume"
    exit 1
  fi
done
rows=$(($(wc -l < "$work/whole/progress.csv") - 1))
echo "kill -9 and resume: identical $rows rows"

#!/usr/bin/env bash
# kill -9 a training run at an arbitrary moment, resume it, and compare its progress.csv with an
# uninterrupted run's (the wall-clock columns Time and MsPerPlan aside).
# Usage: kill_resume_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
cmbrl=$1 config=$2 work=$3
rm -rf "$work" && mkdir -p "$work"

"$cmbrl" train --config "$config" --steps 1200 --out "$work/whole" > /dev/null
for delay in 0.7 1.9; do
  run="$work/killed-$delay"
  "$cmbrl" train --config "$config" --steps 1200 --out "$run" > /dev/null &
  pid=$!
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" 2> /dev/null || true
  "$cmbrl" train --resume "$run" > /dev/null
  if ! diff <(cut -d, -f1-6,8-11,13- "$work/whole/progress.csv") \
            <(cut -d, -f1-6,8-11,13- "$run/progress.csv"); then
    echo "FAILED: rows differ after kill -9 at ${delay}s and resume"
    exit 1
  fi
done
rows=$(($(wc -l < "$work/whole/progress.csv") - 1))
echo "kill -9 and resume: identical $rows rows"

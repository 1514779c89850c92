#!/usr/bin/env bash
# kill -9 a training run at an arbitrary moment of its life (once its directory holds a run),
# resume it, and compare its progress.csv with an uninterrupted run's (the clock columns Time,
# MsPerPlan and CpuTime aside): with checkpoints after each episode, and after every agent step
# (--checkpoint-seconds 0, so that the kill lands in the middle of an episode). Then SIGTERM:
# the run checkpoints where it is, exits with 143, and resumes to the same rows.
# Usage: kill_resume_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1 config=$2 work=$3
rm -rf "$work" && mkdir -p "$work"

"$cmbrl" train --config "$config" --steps 1200 --out "$work/whole" > /dev/null
for kill in "0.3 300" "1.5 300" "1.5 0"; do
  read -r delay every <<< "$kill"
  run="$work/killed-$delay-$every"
  "$cmbrl" train --config "$config" --steps 1200 --out "$run" --checkpoint-seconds "$every" \
    > /dev/null &
  pid=$!
  # The run exists once config.yaml is in place (the program may still be loading LibTorch).
  for _ in $(seq 300); do [ -f "$run/config.yaml" ] && break; sleep 0.1; done
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" 2> /dev/null || true
  "$cmbrl" train --resume "$run" > /dev/null
  if ! diff <(deterministic_rows "$work/whole/progress.csv") \
            <(deterministic_rows "$run/progress.csv"); then
    echo "FAILED: rows differ after kill -9 at ${delay}s (checkpoints every ${every}s) and resume"
    exit 1
  fi
done

run="$work/terminated"
"$cmbrl" train --config "$config" --steps 1200 --out "$run" > /dev/null 2> "$work/terminated.err" &
pid=$!
# Signalled once its first row is written, not after a fixed delay: on an idle fast machine the
# whole run took under 1.5 s from its first row, and the signal came after its end.
for _ in $(seq 300); do
  [ -f "$run/progress.csv" ] && [ "$(wc -l < "$run/progress.csv")" -ge 2 ] && break
  sleep 0.05
done
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
if [ "$status" -ne 143 ] || ! grep -q "SIGTERM stopped the run; its last checkpoint is at step" "$work/terminated.err"; then
  echo "FAILED: SIGTERM gave exit status $status (expected 143 after a checkpoint):"
  cat "$work/terminated.err"
  exit 1
fi
"$cmbrl" train --resume "$run" > /dev/null
if ! diff <(deterministic_rows "$work/whole/progress.csv") \
          <(deterministic_rows "$run/progress.csv"); then
  echo "FAILED: rows differ after SIGTERM and resume"
  exit 1
fi
rows=$(($(wc -l < "$work/whole/progress.csv") - 1))
echo "kill -9 and resume: identical $rows rows"

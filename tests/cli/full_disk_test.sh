#!/usr/bin/env bash
# A full disk is an error that names the file and the cause, never a crash or a silent loss:
# a tmpfs of a few hundred kB fills while a checkpoint, a report, a rollout trace and a sweep's
# slurm.sh are written. Each command must exit 1 naming the file and "No space left on device";
# the run keeps its last whole checkpoint and, once space is freed, resumes to the rows of a run
# made in one go. Needs root (mount); exits 77 (skipped) without it.
# Usage: full_disk_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1 config=$2 work=$3
if [ "$(id -u)" != 0 ]; then echo "skipped: mounting a tmpfs needs root"; exit 77; fi
rm -rf "$work" && mkdir -p "$work/disk"
if ! mount -t tmpfs -o size=300k tmpfs "$work/disk" 2> /dev/null; then
  echo "skipped: cannot mount a tmpfs here (no CAP_SYS_ADMIN)"; exit 77
fi
trap 'umount "$work/disk" 2> /dev/null || true' EXIT
disk=$work/disk
expect_full() {  # what, log, file it must name
  if ! grep -q "could not write '[^']*$3': No space left on device" "$2"; then
    echo "FAILED: $1 did not name '$3' and the cause:"; cat "$2"; exit 1
  fi
  if grep -qiE 'terminate called|Aborted|c10::Error|Traceback' "$2"; then
    echo "FAILED: $1 crashed:"; cat "$2"; exit 1
  fi
}

# 1. A checkpoint that does not fit (the second one needs the first's space again).
"$cmbrl" train --config "$config" --steps 600 --out "$work/whole" > /dev/null
set +e
"$cmbrl" train --config "$config" --steps 600 --out "$disk/run" > "$work/train.log" 2>&1
code=$?
set -e
[ "$code" = 1 ] || { echo "FAILED: train exited $code on a full disk"; cat "$work/train.log"; exit 1; }
expect_full train "$work/train.log" "checkpoint.tmp/[a-z_]*\.[a-z]*"
[ -f "$disk/run/checkpoint/manifest.json" ] || { echo "FAILED: the last checkpoint is gone"; exit 1; }
[ ! -e "$disk/run/checkpoint.tmp" ] || { echo "FAILED: the half-written checkpoint stayed"; exit 1; }
# Space freed (the run moved to a disk with room): it resumes to the uninterrupted run's rows.
cp -r "$disk/run" "$work/moved" && rm -f "$work/moved/lock" && rm -rf "$disk/run"
"$cmbrl" train --resume "$work/moved" > /dev/null
if ! diff <(deterministic_rows "$work/whole/progress.csv") \
          <(deterministic_rows "$work/moved/progress.csv"); then
  echo "FAILED: the resumed run's rows differ from the uninterrupted run's"; exit 1
fi

# 2. A report whose pictures do not fit.
mkdir -p "$work/sweep/runs" && cp -r "$work/whole" "$work/sweep/runs/whole" && rm -f "$work/sweep/runs/whole/lock"
head -c $((280 * 1024)) /dev/zero > "$disk/filler" 2> /dev/null || true
set +e
"$cmbrl" report "$work/sweep" --out "$disk/report" --window 300 > "$work/report.log" 2>&1
code=$?
set -e
[ "$code" = 1 ] || { echo "FAILED: report exited $code on a full disk"; cat "$work/report.log"; exit 1; }
expect_full report "$work/report.log" "report/[^']*"
rm -f "$disk/filler"

# 3. A rollout trace.
head -c $((290 * 1024)) /dev/zero > "$disk/filler" 2> /dev/null || true
set +e
"$cmbrl" rollout --episodes 3 --trace "$disk/trace.jsonl" > "$work/rollout.log" 2>&1
code=$?
set -e
[ "$code" = 1 ] || { echo "FAILED: rollout exited $code on a full disk"; cat "$work/rollout.log"; exit 1; }
expect_full rollout "$work/rollout.log" "trace.jsonl"
rm -f "$disk/filler" "$disk/trace.jsonl"

# 4. A sweep's own files (its lock, sweep.json, then slurm.sh), before any run starts.
mkdir -p "$disk/sweep"
head -c $((298 * 1024)) /dev/zero > "$disk/filler" 2> /dev/null || true
set +e
mkdir -p "$work/configs"
sed "s/^planner: .*/planner: random/" "$config" > "$work/configs/pointgoal1-random.yaml"
"$cmbrl" sweep --config-dir "$work/configs" --tasks PointGoal1 --planners random \
  --seeds 0 --steps 100 --out "$disk/sweep" > "$work/sweep.log" 2>&1
code=$?
set -e
[ "$code" = 1 ] || { echo "FAILED: sweep exited $code on a full disk"; cat "$work/sweep.log"; exit 1; }
expect_full sweep "$work/sweep.log" "\(lock\|slurm.sh\|sweep.json.tmp\)"
[ ! -e "$disk/sweep/runs/pointgoal1-random-s0/config.yaml" ] || { echo "FAILED: a run started"; exit 1; }
rm -rf "$disk/sweep" "$disk/filler"

# 5. A first checkpoint that does not fit, for a model-free run (a row is written before it) and
# an MPC run: each resumes, once moved to a disk with room, from its beginning to the rows of a
# run made in one go, and its session says why.
first_checkpoint() {  # name, config
  "$cmbrl" train --config "$2" --out "$work/whole-$1" > /dev/null 2>&1
  local avail; avail=$(df --output=avail -B1 "$disk" | tail -1)
  head -c $((avail - 40960)) /dev/zero > "$disk/filler" 2> /dev/null || true
  set +e
  "$cmbrl" train --config "$2" --out "$disk/$1" > "$work/first-$1.log" 2>&1
  code=$?
  set -e
  [ "$code" = 1 ] || { echo "FAILED: $1 exited $code on a full disk"; cat "$work/first-$1.log"; exit 1; }
  expect_full "$1" "$work/first-$1.log" "checkpoint.tmp/[a-z_]*\.[a-z]*"
  [ ! -e "$disk/$1/checkpoint" ] || { echo "FAILED: $1 has a checkpoint after all"; exit 1; }
  grep -q "the run has no checkpoint yet: free space, then resume it" "$work/first-$1.log" ||
    { echo "FAILED: $1's message does not say it has no checkpoint yet"; cat "$work/first-$1.log"; exit 1; }
  cp -r "$disk/$1" "$work/moved-$1" && rm -f "$work/moved-$1/lock" && rm -rf "$disk/$1" "$disk/filler"
  "$cmbrl" train --resume "$work/moved-$1" > /dev/null 2>&1 ||
    { echo "FAILED: $1 did not resume after its first checkpoint failed"; exit 1; }
  if ! diff <(deterministic_rows "$work/whole-$1/progress.csv") \
            <(deterministic_rows "$work/moved-$1/progress.csv"); then
    echo "FAILED: $1's resumed rows differ from the uninterrupted run's"; exit 1
  fi
  grep -q "first checkpoint was never completed" "$work/moved-$1/sessions.jsonl" ||
    [ "$1" = mpc ] || { echo "FAILED: $1's session does not say it started again"; exit 1; }
}
first_checkpoint model-free "$(dirname "${BASH_SOURCE[0]}")/tiny-cpo.yaml"
first_checkpoint mpc "$config"

# 6. The lock file on a full disk names the cause (it once read "Success").
cp -r "$work/whole-mpc" "$disk/locked" && rm -f "$disk/locked/lock"
head -c $(( $(df --output=avail -B1 "$disk" | tail -1) )) /dev/zero > "$disk/filler" 2> /dev/null || true
set +e
"$cmbrl" train --resume "$disk/locked" --steps 999 > "$work/lock.log" 2>&1
code=$?
set -e
[ "$code" = 1 ] || { echo "FAILED: a resume exited $code with no room for its lock"; cat "$work/lock.log"; exit 1; }
grep -q "could not write '[^']*locked/lock': No space left on device" "$work/lock.log" ||
  { echo "FAILED: the lock's error names no cause:"; cat "$work/lock.log"; exit 1; }
rm -rf "$disk/locked" "$disk/filler"
echo "full disk: train, report, rollout trace and sweep named the file and the cause; resumed exactly; a first checkpoint that did not fit resumed from the start (model-free and MPC); the lock named its cause"

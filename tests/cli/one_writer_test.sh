#!/usr/bin/env bash
# One writer per run: 20 processes start the same new run at once. Exactly one trains it; each
# other refuses with a clear message and touches nothing; the run then equals one made alone
# (its rows, the clock columns Time, MsPerPlan and CpuTime aside), and resumes.
# Usage: one_writer_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1 config=$2 work=$3
rm -rf "$work" && mkdir -p "$work/logs"
"$cmbrl" train --config "$config" --steps 60 --out "$work/alone" > /dev/null
for i in $(seq 20); do
  "$cmbrl" train --config "$config" --steps 60 --out "$work/run" > "$work/logs/$i.log" 2>&1 &
done
ok=0 refused=0
for job in $(jobs -p); do
  if wait "$job"; then ok=$((ok + 1)); else refused=$((refused + 1)); fi
done
[ "$ok" -eq 1 ] || { echo "expected one start to succeed, $ok did"; cat "$work"/logs/*.log; exit 1; }
# A loser refused after the winner wrote its config says "already holds a run"; one that got
# past that check first (a loaded machine starts processes slowly) is refused the lock: "in use
# by another cmbrl process".
unclear=$(grep -L -e "already holds a run" -e "another process" -e "in use by another cmbrl process" \
  -e '"run"' "$work"/logs/*.log || true)
[ -z "$unclear" ] || { echo "unclear refusals:"; cat $unclear; exit 1; }
rows() { deterministic_rows "$1/progress.csv"; }
diff <(rows "$work/alone") <(rows "$work/run") || { echo "the raced run differs"; exit 1; }
"$cmbrl" train --resume "$work/run" --steps 120 > /dev/null
echo "one writer: 1 of 20 simultaneous starts trained, $refused refused, rows as a run alone"

#!/usr/bin/env bash
# kill -9 a sweep while its runs train, start it again, and compare every run's progress.csv with
# an uninterrupted sweep's (the clock columns Time, MsPerPlan and CpuTime aside): no row may be
# missing or repeated. Also checks that the killed sweep left no training process behind and
# that a second start skips what is finished, that runs at a time get CPUs of their own, and that
# a second sweep of a folder being swept is refused.
# Usage: sweep_resume_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1 config=$2 work=$3
rm -rf "$work" && mkdir -p "$work/configs"
for planner in rce random; do
  sed "s/^planner: .*/planner: $planner/" "$config" > "$work/configs/pointgoal1-$planner.yaml"
done
sweep=(sweep --tasks PointGoal1 --planners rce random --seeds 0 1 --config-dir "$work/configs"
       --steps 400 --jobs 2)

"$cmbrl" "${sweep[@]}" --out "$work/whole" > /dev/null

# Kill once a run is mid-way: two or more rows written, not all (a count over all runs could be
# met by a fast run that already finished beside one that has not begun).
full=$(wc -l < "$work/whole/runs/pointgoal1-rce-s0/progress.csv")
midway() {
  local progress lines
  for progress in "$work"/cut/runs/*/progress.csv; do
    lines=$(wc -l < "$progress" 2> /dev/null || echo 0)
    [ "$lines" -ge 3 ] && [ "$lines" -lt "$full" ] && return 0
  done
  return 1
}
# The process ids of the cut sweep's trainers: those whose command line names its runs, read
# from /proc in one pass, fast enough to follow the look that saw a run mid-way (no procps
# needed). The grep that reads them names the runs too, and is left out, as are processes gone.
cut_trainers() {
  local cmdline pid comm
  grep -l -a -F -- "$work/cut/runs" /proc/[0-9]*/cmdline 2> /dev/null |
    while read -r cmdline; do
      pid=${cmdline#/proc/} && pid=${pid%/cmdline}
      if comm=$(cat "/proc/$pid/comm" 2> /dev/null) && [ "$comm" != grep ]; then echo "$pid"; fi
    done
}
# Whether any of the cut sweep's trainers is still alive.
trainers_alive() { [ -n "$(cut_trainers)" ]; }
# Once a run is seen mid-way, the sweep and its trainers are frozen, so that they are still
# mid-way at the kill however long the checks below take on a loaded machine. A tiny run can pass
# its middle between two looks, or between the look and the freeze: a sweep not frozen mid-way
# is killed and started afresh, up to 5 times.
seen=false
for attempt in 1 2 3 4 5; do
  rm -rf "$work/cut"
  "$cmbrl" "${sweep[@]}" --out "$work/cut" > "$work/cut-1.log" &
  pid=$!
  for _ in $(seq 1500); do
    midway && break
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.02
  done
  frozen=$(cut_trainers)
  kill -STOP "$pid" $frozen 2> /dev/null || true
  midway && { seen=true; break; }
  echo "attempt $attempt: the sweep was not frozen mid-way; starting it again"
  kill -9 "$pid" 2> /dev/null || true
  kill -CONT $frozen 2> /dev/null || true
  wait "$pid" 2> /dev/null || true
  for _ in $(seq 100); do trainers_alive || break; sleep 0.1; done
done
$seen || { echo "FAILED: in 5 attempts no run of the sweep was frozen mid-way"; exit 1; }
# A second sweep of the same folder meanwhile is refused by name (it would take the first's
# runs, locked by their trainers, for failed ones).
if "$cmbrl" "${sweep[@]}" --out "$work/cut" > "$work/second.log" 2>&1; then
  echo "FAILED: a second sweep of a folder being swept was accepted"; exit 1
fi
grep -q "cut' is in use by another cmbrl process (pid $pid" "$work/second.log" ||
  { cat "$work/second.log"; echo "FAILED: the second sweep's refusal does not name the first"; exit 1; }
kill -9 "$pid"
kill -CONT $frozen 2> /dev/null || true  # they now take their parent's death (SIGTERM)
wait "$pid" 2> /dev/null || true
for _ in $(seq 100); do trainers_alive || break; sleep 0.1; done
if trainers_alive; then
  echo "FAILED: training processes outlived the killed sweep"
  exit 1
fi
# With 2 or more CPUs, each of the 2 runs at a time gets its own.
if [ "$(nproc)" -ge 2 ] && ! grep -q '"cpus":\[0\]' "$work/cut-1.log"; then
  echo "FAILED: the first run was not given CPU 0 alone"
  exit 1
fi
"$cmbrl" "${sweep[@]}" --out "$work/cut" > "$work/cut-2.log"
grep -q '"status":"resumed"' "$work/cut-2.log" || { echo "FAILED: nothing was resumed"; exit 1; }

runs=0
for whole in "$work"/whole/runs/*/progress.csv; do
  name=$(basename "$(dirname "$whole")")
  cut_run="$work/cut/runs/$name/progress.csv"
  if ! diff <(deterministic_rows "$whole") <(deterministic_rows "$cut_run"); then
    echo "FAILED: $name differs after kill -9 and restart"
    exit 1
  fi
  episodes=$(tail -n +2 "$cut_run" | cut -d, -f2 | sort -n | uniq | wc -l)
  [ "$episodes" -eq $(($(wc -l < "$cut_run") - 1)) ] || { echo "FAILED: $name repeats an episode"; exit 1; }
  runs=$((runs + 1))
done
"$cmbrl" "${sweep[@]}" --out "$work/cut" | grep -q '"already_finished":4' ||
  { echo "FAILED: a third start did not skip the 4 finished runs"; exit 1; }
# The report keeps the runs' logs, and makes the same table again from them alone, or from them
# beside the sweep; --complete leaves out runs short of the window and says so.
"$cmbrl" report "$work/whole" --out "$work/report" --window 300 > /dev/null
"$cmbrl" report "$work/report" --out "$work/again" --window 300 > /dev/null
"$cmbrl" report "$work/report" "$work/whole" --out "$work/both" --window 300 > /dev/null
for copy in again both; do
  cmp -s "$work/report/table-1.csv" "$work/$copy/table-1.csv" ||
    { echo "FAILED: the report made from its logs ($copy) differs"; exit 1; }
done
# A report's log of a run's first episode only.
short="$work/short/run-logs/pointgoal1-rce-short"
mkdir -p "$short" && cp "$work/whole/runs/pointgoal1-rce-s0/config.yaml" "$short/"
head -n 2 "$work/whole/runs/pointgoal1-rce-s0/progress.csv" > "$short/progress.csv"
refused=$("$cmbrl" report "$work/short" --out "$work/short-report" --window 300 --complete 2>&1 ||
  true)
grep -q 'no run has reached the window of 300 steps' <<< "$refused" ||
  { echo "FAILED: --complete kept a run short of the window: $refused"; exit 1; }
"$cmbrl" report "$work/short" "$work/whole" --out "$work/short-report" --window 300 \
  --complete > /dev/null
grep -q 'left out, short of the window: pointgoal1-rce-short (100 steps)' \
  "$work/short-report/report.md" || { echo "FAILED: the report names no run left out"; exit 1; }
# A run whose checkpoint manifest was deleted is not "already finished": the sweep resumes it,
# and the resume names what is wrong.
rm "$work/cut/runs/pointgoal1-rce-s0/checkpoint/manifest.json"
again=$("$cmbrl" "${sweep[@]}" --out "$work/cut" 2>&1 || true)
grep -q '"already_finished":3' <<< "$again" ||
  { echo "FAILED: a run without its manifest passed as finished: $again"; exit 1; }
grep -q 'pointgoal1-rce-s0' <<< "$again" && grep -qi 'checkpoint' "$work/cut/logs/pointgoal1-rce-s0.log" ||
  { echo "FAILED: the resume of a run without its manifest named nothing"; exit 1; }
# A report over a run whose config.yaml was deleted refuses it by name.
rm "$work/whole/runs/pointgoal1-random-s1/config.yaml"
refused=$("$cmbrl" report "$work/whole" --out "$work/no-config" --window 300 2>&1 || true)
grep -q 'pointgoal1-random-s1' <<< "$refused" && grep -q 'config.yaml' <<< "$refused" ||
  { echo "FAILED: a run without its config.yaml was reported: $refused"; exit 1; }
echo "sweep killed and restarted: $runs runs with identical rows"

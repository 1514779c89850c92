#!/usr/bin/env bash
# An experiment declared as data, end to end: `cmbrl sweep EXPERIMENT` makes its runs, `cmbrl
# report EXPERIMENT` its report; the report made again from its own logs alone (the runs
# deleted, as in a fresh clone) is the same but for the line that says when it was made; a
# declaration edited after its runs is refused, naming the run and the key.
# Usage: experiment_test.sh CMBRL CONFIGS_DIR WORK_DIR
set -euo pipefail
cmbrl=$1 configs=$2 work=$3
rm -rf "$work" && mkdir -p "$work/experiments/tiny"
ln -s "$configs" "$work/configs"
cat > "$work/experiments/tiny/experiment.yaml" << 'YAML'
family: paper
tasks: [PointGoal1]
methods: [rce, random]
seeds: [0, 1]
window: 120
set:
  training: {pretrain_episodes: 6, pretrain_steps: 20, episodes_per_epoch: 2, total_steps: 120}
  ensemble: {hidden_sizes: [16], max_epochs: 5}
  classifier: {rounds: 10}
  planning: {horizon: 3, population: 24, elites: 6, min_feasible_elites: 3, max_iterations: 2,
             random_samples: 50}
axes:
  objective.gamma: [0.98, 0.9]
YAML
cd "$work"
# --status starts nothing: before the runs, 8 new runs of 120 steps each.
"$cmbrl" sweep experiments/tiny --status > status-before.log
grep -qF '{"run":"pointgoal1-rce-gamma=0.98-s0","status":"new","steps":0,"budget":120}' \
  status-before.log || { cat status-before.log; exit 1; }
grep -qF '"runs":8,"finished":0,"started":0,"new":8,"steps":0,"budget":960,"seconds":0.0}' \
  status-before.log || { cat status-before.log; exit 1; }
[ ! -e experiments/tiny/runs/runs ] || { echo "--status started a run"; exit 1; }
if "$cmbrl" sweep experiments/tiny --status --jobs 2 > /dev/null 2> status-jobs.err; then
  echo "--status with --jobs was accepted"; exit 1
fi
grep -q -- "--jobs starts runs; --status starts none" status-jobs.err || { cat status-jobs.err; exit 1; }
"$cmbrl" sweep experiments/tiny --jobs 2 > sweep.log
"$cmbrl" sweep experiments/tiny --status > status-after.log
grep -qE '"runs":8,"finished":8,"started":0,"new":0,"steps":960,"budget":960,"seconds":[0-9.]+}' \
  status-after.log || { cat status-after.log; exit 1; }
# Each run says how long it trained: its last row's Time, or its last checkpoint's, a moment on.
time=$(tail -n 1 experiments/tiny/runs/runs/pointgoal1-rce-gamma=0.98-s0/progress.csv | cut -d, -f7)
seconds=$(grep '"run":"pointgoal1-rce-gamma=0.98-s0"' status-after.log |
  sed -n 's/.*"seconds":\([0-9.]*\)}$/\1/p')
awk -v t="$time" -v s="$seconds" 'BEGIN { exit !(s != "" && s >= t - 0.05 && s < t + 5) }' ||
  { echo "status seconds '$seconds' against the last row's Time $time"; cat status-after.log; exit 1; }
runs=$(ls experiments/tiny/runs/runs | wc -l)
[ "$runs" -eq 8 ] || { echo "expected 8 runs (2 methods x 2 gammas x 2 seeds), got $runs"; exit 1; }
"$cmbrl" report experiments/tiny > /dev/null
grep -q "SHA-256 $(sha256sum experiments/tiny/experiment.yaml | cut -d' ' -f1)" \
  experiments/tiny/report/report.md || { echo "the report lacks the file's SHA-256"; exit 1; }
# Each value of the axis is a cell of its own (2 seeds each), compared with the first value.
for row in "| PointGoal1 (gamma=0.9) | MPC-RCE | 2 |" "| PointGoal1 (gamma=0.98) | MPC-random | 2 |" \
           "## Settings compared" "| PointGoal1 | MPC-RCE | gamma=0.9 | gamma=0.98 | 0, 1 |" \
           "## Compute" "8 runs took"; do
  grep -qF "$row" experiments/tiny/report/report.md ||
    { echo "the report lacks '$row'"; sed -n '/## Every cell/,/## Details/p' experiments/tiny/report/report.md; exit 1; }
done
cp -r experiments/tiny/report first-report
rm -rf experiments/tiny/runs
"$cmbrl" report experiments/tiny > /dev/null
diff -r -I '^Made by `cmbrl report' first-report experiments/tiny/report ||
  { echo "the report made again from its logs differs"; exit 1; }
# A fresh clone (no runs/): the report's logs say every run is finished, so a sweep starts none.
"$cmbrl" sweep experiments/tiny --status > status-clone.log
grep -qE '\{"run":"pointgoal1-rce-gamma=0.98-s0","status":"finished","steps":201,"budget":120,"seconds":[0-9.]+,"in_report":true\}' \
  status-clone.log || { cat status-clone.log; exit 1; }
"$cmbrl" sweep experiments/tiny --jobs 2 > sweep-clone.log
[ "$(grep -c '"already finished (in the report)"' sweep-clone.log)" -eq 8 ] || { cat sweep-clone.log; exit 1; }
[ -z "$(ls experiments/tiny/runs/runs)" ] || { echo "a run finished in the report was run again"; exit 1; }
# One run's logs gone: only it is made, by the program --train-with names.
printf '#!/bin/sh\necho "$@" >> %s/trained-with.log\nexec %s "$@"\n' "$PWD" "$cmbrl" > old-cmbrl
chmod +x old-cmbrl
rm -r experiments/tiny/report/run-logs/pointgoal1-random-gamma=0.9-s1
"$cmbrl" sweep experiments/tiny --jobs 2 --train-with old-cmbrl > sweep-one.log
grep -q '^train --config .* --seed 1 --out .*/pointgoal1-random-gamma=0.9-s1$' trained-with.log &&
  [ "$(wc -l < trained-with.log)" -eq 1 ] || { cat trained-with.log sweep-one.log; exit 1; }
if "$cmbrl" sweep experiments/tiny --train-with experiments/tiny/experiment.yaml 2> train-with.err; then
  echo "a --train-with that is not a program was accepted"; exit 1
fi
grep -q -- "--train-with is '.*experiment.yaml': expected an executable" train-with.err ||
  { cat train-with.err; exit 1; }
sed -i 's/rounds: 10/rounds: 11/' experiments/tiny/experiment.yaml
if "$cmbrl" report experiments/tiny 2> edited.err; then
  echo "a report of runs made under another declaration was accepted"; exit 1
fi
grep -q "was made with another config than" edited.err || { cat edited.err; exit 1; }
grep -q "rounds: 10" edited.err || { cat edited.err; exit 1; }
echo "experiment: --status before and after, 8 runs, a cell per setting, report made again identical, a fresh clone runs only what its report lacks, edited declaration refused"

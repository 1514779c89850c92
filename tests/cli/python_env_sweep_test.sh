#!/bin/bash
# A Python environment declared by name in a config (section python) trains from the command
# line, from another folder; resumes after kill -9 to the same rows; evaluates; and an experiment
# of tasks of its own (that environment and the arm task file) sweeps and reports from its
# declaration. Its bad names are refused before a run directory exists.
# usage: python_env_sweep_test.sh CMBRL EXAMPLES_DIR WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1; examples=$2; work=$3
rm -rf "$work"; mkdir -p "$work/exp/presets"
cd "$work"
cp "$examples/custom_env.py" my_env.py  # the user's module, beside the config
sizes='training: {pretrain_episodes: 3, pretrain_steps: 40, episodes_per_epoch: 1, total_steps: 300}
ensemble: {hidden_sizes: [16], max_epochs: 3}
classifier: {rounds: 5}
planning: {horizon: 3, population: 24, elites: 6, min_feasible_elites: 3, max_iterations: 2}'
cat > di.yaml <<YAML
python: {env: "my_env:DoubleIntegrator", reward: "my_env:reward", path: [.]}
$sizes
YAML
mkdir elsewhere && cd elsewhere
"$cmbrl" train --config ../di.yaml --out whole > /dev/null
grep -q "task: python:my_env.DoubleIntegrator()" whole/config.yaml || { echo "no task recorded"; exit 1; }
grep -q "path: \[$work\]" whole/config.yaml || { echo "no absolute python.path"; cat whole/config.yaml; exit 1; }
grep -q '"python_functions":"env=my_env.DoubleIntegrator(), reward=my_env.reward"' whole/sessions.jsonl ||
  { echo "the session names no functions"; exit 1; }
head -1 whole/progress.csv | grep -q ",EpRawCost,CpuTime$" || { echo "no raw cost column"; exit 1; }
rows=$(($(wc -l < whole/progress.csv) - 1))
[ "$rows" -ge 2 ] || { echo "expected episodes, got $rows rows"; exit 1; }
# Killed in the middle of an episode (the env pickles), resumed: the same rows.
killed_mid_episode_resumes "$cmbrl" whole cut --config ../di.yaml
"$cmbrl" eval --run whole --episodes 1 | grep -q '"steps":100' || { echo "eval gave no episode"; exit 1; }
# Drawn by the env itself: its factory takes render_mode, and eval makes one with rgb_array.
"$cmbrl" eval --run whole --episodes 1 --render pictures | grep -q '"picture":"pictures/episode-0.png"' ||
  { echo "eval --render drew nothing"; exit 1; }
[ -s pictures/episode-0.png ] || { echo "no picture"; exit 1; }
# One whose factory cannot draw is named.
printf 'import my_env\n\ndef plain():\n    return my_env.DoubleIntegrator()\n' > ../plain_env.py
printf 'python: {env: "plain_env:plain", reward: "my_env:reward", path: [.]}\n%s\n' "$sizes" > ../plain.yaml
"$cmbrl" train --config ../plain.yaml --out plain --steps 120 2> /dev/null > /dev/null
if "$cmbrl" eval --run plain --render plain-pictures 2> err.txt > /dev/null; then echo "no frames, yet rendered"; exit 1; fi
grep -q "the run's environment draws no pictures" err.txt || { echo "render: $(cat err.txt)"; exit 1; }
cd "$work"
# Bad names, refused before anything is written.
refused() {  # NAME EXPECTED-TEXT PYTHON-SECTION
  printf 'python: %s\n%s\n' "$3" "$sizes" > "bad-$1.yaml"
  if "$cmbrl" train --config "bad-$1.yaml" --out "bad-$1" 2> err.txt; then echo "bad $1 accepted"; exit 1; fi
  grep -q "$2" err.txt || { echo "bad $1: $(cat err.txt)"; exit 1; }
  [ ! -e "bad-$1" ] || { echo "bad $1 left a run directory"; exit 1; }
}
refused module "python.env is 'no_such_env:Env': importing module 'no_such_env' raised ModuleNotFoundError" \
  '{env: "no_such_env:Env", reward: "my_env:reward", path: [.]}'
refused attribute "python.reward is 'my_env:rewrd': 'my_env' has no attribute 'rewrd'" \
  '{env: "my_env:DoubleIntegrator", reward: "my_env:rewrd", path: [.]}'
refused form "python.env is 'my_env.DoubleIntegrator': expected 'module:attribute'" \
  '{env: "my_env.DoubleIntegrator", reward: "my_env:reward", path: [.]}'
# An experiment of tasks of its own: the Python env and the arm task file, RCE and CEM.
cp -r "$examples/arm-reach" arm-reach
for method in rce cem; do
  cat > "exp/presets/doubleintegrator-$method.yaml" <<YAML
task: DoubleIntegrator
planner: $method
python: {env: "my_env:DoubleIntegrator", reward: "my_env:reward", path: [../..]}
$sizes
YAML
  sed -e "s/^planner: rce/planner: $method/" -e "s#model: arm.xml#model: ../../arm-reach/arm.xml#" \
    -e '/^training:/d;/^ensemble:/d;/^classifier:/d;/^planning:/d' arm-reach/task.yaml > "exp/presets/armreach-$method.yaml"
  echo "$sizes" >> "exp/presets/armreach-$method.yaml"
done
cat > exp/experiment.yaml <<YAML
family: paper
configs: presets
tasks: [DoubleIntegrator, ArmReach]
methods: [rce, cem]
seeds: [0]
window: 200
set: {training.total_steps: 200}
YAML
"$cmbrl" sweep exp --jobs 2 > sweep.json
"$cmbrl" report exp > /dev/null
for run in doubleintegrator-rce-s0 doubleintegrator-cem-s0 armreach-rce-s0 armreach-cem-s0; do
  [ -f "exp/report/run-logs/$run/progress.csv" ] || { echo "no logs of $run"; ls -R exp/report; exit 1; }
done
grep -q "DoubleIntegrator" exp/report/report.md || { echo "the report names no DoubleIntegrator"; exit 1; }
# A report pools a task's runs: one name made on another environment is refused.
mkdir -p other/run-logs  # a report's logs (no checkpoint guards their config)
cp -r exp/report/run-logs/doubleintegrator-rce-s0 other/run-logs/doubleintegrator-rce-s1
sed -i 's/env: "\{0,1\}my_env:DoubleIntegrator"\{0,1\}/env: my_env:Elsewhere/' other/run-logs/doubleintegrator-rce-s1/config.yaml
grep -q "env: my_env:Elsewhere" other/run-logs/doubleintegrator-rce-s1/config.yaml || { echo "sed missed"; exit 1; }
if "$cmbrl" report exp/runs other --out pooled 2> err.txt > /dev/null; then echo "different envs pooled"; exit 1; fi
grep -q "both name task 'DoubleIntegrator' but were made on different environments (python.env my_env:Elsewhere)" err.txt ||
  { echo "pooling: $(cat err.txt)"; exit 1; }
echo "python env by name: trained, resumed after kill -9 to identical $rows rows, evaluated and drawn, 3 bad names refused, its experiment swept 4 runs and reported, another env under its name refused"

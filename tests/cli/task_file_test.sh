#!/bin/bash
# A task declared as a file trains from the command line, resumes to the same rows after a kill,
# evaluates, and its bad inputs are refused by name before the run directory exists.
# usage: task_file_test.sh CMBRL EXAMPLES_DIR WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1; examples=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
# The example's task (a copy), at a tiny size, from another folder: its model is found from
# the task file's folder.
cat > "$work/tiny.yaml" <<YAML
training: {pretrain_episodes: 3, pretrain_steps: 40, episodes_per_epoch: 1, total_steps: 120}
ensemble: {hidden_sizes: [16], max_epochs: 3}
classifier: {rounds: 5}
planning: {horizon: 3, population: 24, elites: 6, min_feasible_elites: 3, max_iterations: 2}
YAML
cd "$work"
cp -r "$examples/arm-reach" arm-reach  # bad copies are written beside it, not in the sources
examples="$work"
task="$examples/arm-reach/task.yaml"
"$cmbrl" train --config "$task" tiny.yaml --out whole > /dev/null
grep -q "model: $examples/arm-reach/arm.xml" whole/config.yaml || { echo "config names no absolute model"; exit 1; }
rows=$(($(wc -l < whole/progress.csv) - 1))
[ "$rows" -ge 2 ] || { echo "expected episodes, got $rows rows"; exit 1; }
# Stopped within its first episode, resumed: the same rows.
killed_mid_episode_resumes "$cmbrl" whole cut --config "$task" tiny.yaml
"$cmbrl" eval --run whole --episodes 1 > eval.jsonl
grep -q '"steps":100' eval.jsonl || { echo "eval gave no episode"; exit 1; }
# No goals, hazards or vases in this world: none counted as 0.
! grep -q 'goal\|hazard\|vase' eval.jsonl ||
  { echo "eval counts the Goal world's: $(cat eval.jsonl)"; exit 1; }
if "$cmbrl" eval --run whole --render pictures 2> err.txt; then echo "render accepted"; exit 1; fi
grep -q "task 'ArmReach' has neither" err.txt || { echo "render: $(cat err.txt)"; exit 1; }
[ ! -e pictures ] || { echo "render made a folder"; exit 1; }
# Bad inputs, named, and no run directory made.
refused() {  # NAME EXPECTED-TEXT SED-EXPRESSION
  sed "$3" "$task" > "$examples/arm-reach/bad-$1.yaml"
  if "$cmbrl" train --config "$examples/arm-reach/bad-$1.yaml" tiny.yaml --out "bad-$1" 2> err.txt; then
    rm -f "$examples/arm-reach/bad-$1.yaml"; echo "bad $1 accepted"; exit 1
  fi
  rm -f "$examples/arm-reach/bad-$1.yaml"
  grep -q "$2" err.txt || { echo "bad $1: $(cat err.txt)"; exit 1; }
  [ ! -e "bad-$1" ] || { echo "bad $1 left a run directory"; exit 1; }
}
refused sensor "mujoco_task.sensors: the model has no sensor named 'wrist_pos' (its sensors: shoulder_pos" \
  's/elbow_vel, tip_pos\]/elbow_vel, wrist_pos, tip_pos]/'
refused geom "mujoco_task.cost_contact_with: the model has no geom named 'wall'" 's/\[obstacle\]/[wall]/'
refused model "mujoco_task.model: MuJoCo cannot load" 's/model: arm.xml/model: task.yaml/'
refused joint "mujoco_task.reset_joints: the model has no joint named 'wrist'" 's/\[shoulder, elbow\]/[shoulder, wrist]/'
refused form "mujoco_task.reward is 'closeness': expected one of site-distance" 's/reward: site-distance/reward: closeness/'
refused misspelt-form "mujoco_task.reward is 'site-distanse' (did you mean 'site-distance'?)" \
  's/reward: site-distance/reward: site-distanse/'
# A model-free learner on the same task: each 300-step epoch ends three 100-step episodes, which
# its log line and the session's closing line count (not one per epoch).
cat > cpo.yaml <<YAML
algorithm: cpo
training: {total_steps: 600}
policy_optimisation: {steps_per_epoch: 300, policy_hidden: [8], value_hidden: [8],
                      value_iterations: 2}
YAML
"$cmbrl" train --config "$task" cpo.yaml --out cpo > cpo.json 2> cpo.log
grep -q '\[epoch 2\] steps 600/600 | 3 episodes | AverageEpRet -\?[0-9.]* | AverageEpCost [0-9.]*' cpo.log \
  || { echo "model-free log: $(cat cpo.log)"; exit 1; }
grep -q '"episodes_this_session":6,"total_env_interacts":600,' cpo.json \
  || { echo "model-free summary: $(cat cpo.json)"; exit 1; }
echo "task file: trained, resumed after kill -9 to identical $rows rows, evaluated, 6 bad inputs" \
  "named, its model-free session's 6 episodes counted"

#!/usr/bin/env bash
# The floors of docs/ARCHITECTURE.md, checked on the sources: a folder of cmbrl/ includes only
# from the folders below it, and the plain-data floors (run/, config/, report/, sweep/) only the
# components' plain-data headers (their *_options.h and the task facts). Prints every include
# that breaks a rule, with its file and line, and fails when there is one.
# Usage: include_layers_test.sh <source dir>
set -euo pipefail
cd "${1:?the source directory}"

# The components' plain-data headers, which the plain floors may read.
plain='models/model_options\.h|planning/planning_options\.h|policy_opt/policy_opt_options\.h'
plain+='|env/variant\.h|env/task_list\.h|env/mujoco_task_options\.h|env/tasks/[a-z_]+_spec\.h'

# What each folder may include (an extended regular expression over the path after cmbrl/).
declare -A allowed=(
  [core]='core/'
  [env]='(core|env)/'
  [viz]='(core|env|viz)/'
  [agent]='(core|env|agent)/'
  [models]='(core|models)/'
  [planning]='(core|models|planning)/'
  [policy_opt]='(core|policy_opt)/'
  [run]="core/|run/|${plain}"
  [config]="core/|run/|config/|${plain}"
  [learners]='(core|env|agent|models|planning|policy_opt|run|config|learners)/'
  [train]='(core|env|agent|models|planning|policy_opt|run|config|learners|train)/'
  [eval]='(core|env|agent|models|planning|policy_opt|run|config|learners|viz|eval)/'
  [report]="core/|run/|config/|viz/|report/|${plain}"
  [sweep]="core/|run/|config/|report/|sweep/|${plain}"
)

broken=0
for folder in cmbrl/*/; do
  name=$(basename "$folder")
  rule=${allowed[$name]:-}
  if [ -z "$rule" ]; then
    echo "cmbrl/$name/ has no floor in include_layers_test.sh: add it with what it may include"
    broken=1
    continue
  fi
  while IFS=: read -r file line text; do
    target=$(sed -E 's/.*#include "cmbrl\/([^"]+)".*/\1/' <<<"$text")
    if ! grep -qE "^(${rule})" <<<"$target"; then
      echo "$file:$line: cmbrl/$name/ includes cmbrl/$target, above its floor (allowed: $rule)"
      broken=1
    fi
  done < <(grep -rnE '^#include "cmbrl/' "$folder" --include='*.h' --include='*.cc' || true)
done
if [ "$broken" -ne 0 ]; then exit 1; fi
echo "every include of cmbrl/ keeps to its floor"

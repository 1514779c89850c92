#!/usr/bin/env bash
# Every committed experiment report regenerates from what is committed: each
# experiments/<name>/report/ is made again, in a copy of the tree that holds only what git
# tracks there (the declaration, configs/, data/reference and the report's own run-logs; no
# runs/ and no checkpoints, as in a fresh clone), and must equal the committed one except for
# the line that says which binary made it and when. A change to the report's code therefore
# fails here until the reports are made again with it and committed.
# Usage: committed_reports_test.sh CMBRL SOURCE_DIR WORK_DIR
set -euo pipefail
cmbrl=$1 source=$2 work=$3
rm -rf "$work" && mkdir -p "$work/tree/experiments" "$work/tree/data"
ln -s "$source/configs" "$work/tree/configs"
cp -r "$source/data/reference" "$work/tree/data/"   # a link would be named by its target

made=0
for report in "$source"/experiments/*/report; do
  [ -f "$report/report.md" ] || continue
  name=$(basename "$(dirname "$report")")
  # An experiment made by a driver of its own (run.py, no experiment.yaml: custom-tasks) is
  # made again by python/tests/test_custom_env.py.
  [ -f "$source/experiments/$name/experiment.yaml" ] || continue
  copy="$work/tree/experiments/$name"
  mkdir -p "$copy"
  cp "$source/experiments/$name/experiment.yaml" "$copy/"
  # An experiment's own presets (its `configs:` folder, committed beside it) come too; one
  # outside it (../../configs/ppo) is already in the tree through the configs/ link.
  presets=$(sed -n 's/^configs:[[:space:]]*\([^#[:space:]]*\).*/\1/p' "$copy/experiment.yaml")
  if [ -n "$presets" ] && [ -d "$source/experiments/$name/$presets" ] &&
     [[ "$presets" != ../* && "$presets" != /* ]]; then
    cp -r "$source/experiments/$name/$presets" "$copy/$presets"
  fi
  cp -r "$report" "$copy/report"   # its run-logs/ are the runs' only committed record
  if ! (cd "$work/tree" &&
        "$cmbrl" report "experiments/$name" --reference data/reference > "$work/$name.log" 2>&1)
  then
    echo "experiments/$name: 'cmbrl report' failed:"; cat "$work/$name.log"; exit 1
  fi
  if ! diff -r -I '^Made by `cmbrl report' "$report" "$copy/report" > "$work/$name.diff"; then
    echo "experiments/$name/report differs from what its committed logs make now:"
    head -40 "$work/$name.diff"
    echo "(remake it with 'cmbrl report experiments/$name' and commit it)"
    exit 1
  fi
  made=$((made + 1))
done
[ "$made" -gt 0 ] || { echo "no committed report found under $source/experiments"; exit 1; }
echo "committed reports: $made made again from their committed logs, identical"

#!/bin/bash
# docs/EXPERIMENTS.md's list of the experiments so far names every experiment folder (one with an
# experiment.yaml), and every README it links to exists.
# usage: experiments_listed_test.sh SOURCE_DIR
set -euo pipefail
source_dir=$1
doc="$source_dir/docs/EXPERIMENTS.md"
status=0
for declaration in "$source_dir"/experiments/*/experiment.yaml; do
  name=$(basename "$(dirname "$declaration")")
  if ! grep -qF "(../experiments/$name/README.md)" "$doc"; then
    echo "experiments/$name is not listed in docs/EXPERIMENTS.md"; status=1
  fi
done
while read -r link; do
  if [ ! -f "$source_dir/docs/$link" ]; then
    echo "docs/EXPERIMENTS.md links to a missing $link"; status=1
  fi
done < <(grep -oE '\(\.\./[^)]*README\.md\)' "$doc" | tr -d '()')
[ "$status" = 0 ] && echo "every experiment is listed"
exit "$status"

#!/bin/bash
# On a terminal `cmbrl train` rewrites one line in place (carriage returns): each rewrite must
# cover what the longer one before it wrote, or the end of that one stays on the screen. Runs
# the tiny RCE config under a pseudo-terminal (`script`, util-linux).
# usage: live_line_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
cmbrl=$1; config=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
command -v script > /dev/null || { echo "FAILED: no script(1) here (Debian's bsdutils)"; exit 1; }
command=$(printf '%q ' "$cmbrl" train --config "$config" --steps 300 --out "$work/run")
script -qec "$command > /dev/null" /dev/null > "$work/terminal"
# The rewrites, in order: the text between carriage returns (the pty turns \n into \r\n).
tr '\r' '\n' < "$work/terminal" | grep '\[epoch' > "$work/rewrites" || true
rewrites=$(wc -l < "$work/rewrites")
if [ "$rewrites" -lt 3 ]; then
  echo "FAILED: $rewrites live lines, expected 3"
  cat -A "$work/terminal"
  exit 1
fi
awk 'length($0) < widest { print "FAILED: line " NR " is " length($0) " wide, after one of " \
       widest ": " $0; bad = 1 } length($0) > widest { widest = length($0) } END { exit bad }' \
  "$work/rewrites"
grep -q 'time left from the next line$' <(head -n 1 "$work/rewrites") ||
  { echo "FAILED: the first live line gives a time left"; exit 1; }
echo "live line: $rewrites rewrites, each as wide as the widest before it"

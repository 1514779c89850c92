#!/usr/bin/env bash
# CMBRL_BUILD_PYTHON=OFF, which CI does not build (a second build of everything): the project
# configures and generates without the Python targets, and the one file compiled otherwise when
# the module is off (app/main.cc, its CMBRL_WITH_PYTHON branch) compiles.
# Usage: without_python_test.sh SOURCE_DIR WORK_DIR GENERATOR
set -euo pipefail
source_dir=$1 work=$2 generator=$3
rm -rf "$work"
# Out of unity batches, so that app/main.cc has a compile command of its own.
cmake -S "$source_dir" -B "$work" -G "$generator" -DCMAKE_BUILD_TYPE=Release \
  -DCMBRL_BUILD_PYTHON=OFF -DCMBRL_UNITY_BUILD=OFF > "$work.log" 2>&1 || { cat "$work.log"; echo "FAILED: configure"; exit 1; }
python3 - "$work/compile_commands.json" "$source_dir/app/main.cc" <<'PY' > "$work/main.sh"
import json, shlex, sys
commands, main = sys.argv[1], sys.argv[2]
(entry,) = [e for e in json.load(open(commands)) if e["file"] == main]
words = shlex.split(entry["command"])
if "-o" in words:
    at = words.index("-o")
    del words[at:at + 2]
words = [w for w in words if not w.endswith("ccache")]
assert "-DCMBRL_WITH_PYTHON" not in words, "main.cc is compiled with the module's definition"
print("cd " + shlex.quote(entry["directory"]) + " && " + shlex.join(words + ["-fsyntax-only"]))
PY
bash "$work/main.sh" || { echo "FAILED: app/main.cc does not compile without Python"; exit 1; }
for rules in "$work/build.ninja" "$work/Makefile"; do
  if [ -f "$rules" ] && grep -q "cmbrl_python" "$rules"; then
    echo "FAILED: a Python target is generated with CMBRL_BUILD_PYTHON=OFF"; exit 1
  fi
done
echo "without Python: configured, generated with no Python target, app/main.cc compiles"

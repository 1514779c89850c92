#!/usr/bin/env bash
# The README's Python snippet, verbatim, in an empty folder, with the package that
# pip_install_test.sh installed into its venv (a test of its own, which runs beside pytest and
# the fault probe rather than after them).
# Usage: readme_snippet_test.sh SOURCE_DIR VENV_DIR
set -euo pipefail
source_dir=$1 venv=$2
[ -x "$venv/bin/python" ] ||
  { echo "FAILED: no venv at $venv (python.pip_install makes it)"; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
awk '/^## Python/{p=1} p&&/^```python/{q=1;next} q&&/^```/{exit} q' "$source_dir/README.md" > snippet.py
[ -s snippet.py ] || { echo "FAILED: no Python snippet in the README"; exit 1; }
"$venv/bin/python" snippet.py > snippet.txt 2>&1 ||
  { cat snippet.txt; echo "FAILED: the README's snippet"; exit 1; }
[ -f my-report/report.md ] || { echo "FAILED: the README's snippet wrote no report"; exit 1; }
echo "README snippet: ran in the installed package's venv and wrote its report"

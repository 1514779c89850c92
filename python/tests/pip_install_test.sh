#!/usr/bin/env bash
# `pip install . --no-build-isolation` into a fresh virtual environment that sees Debian's numpy
# (--system-site-packages), offline, reusing the CMake build folder; then the installed package
# is imported from elsewhere, says the version `cmbrl --version` says, and runs the example. The
# venv stays for readme_snippet_test.sh.
# Usage: pip_install_test.sh SOURCE_DIR BUILD_DIR CMBRL PYTHON VENV_DIR
set -euo pipefail
source_dir=$1 build_dir=$2 cmbrl=$3 python=$4 venv=$5
rm -rf "$venv"
"$python" -m venv --system-site-packages "$venv"
CMBRL_BUILD_DIR=$build_dir "$venv/bin/pip" install --quiet --no-build-isolation --no-deps \
  --no-index "$source_dir"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"  # not the checkout: the installed package must be the one imported
installed=$("$venv/bin/python" -c "import cmbrl, sys; print(cmbrl.__version__); print(cmbrl.__file__, file=sys.stderr)" 2> where)
case "$(cat where)" in "$venv"/*) ;; *) echo "FAILED: imported $(cat where), not the venv's"; exit 1;; esac
package=$(dirname "$(cat where)")
for typed in py.typed __init__.pyi spaces.pyi; do
  [ -f "$package/$typed" ] || { echo "FAILED: the installed package has no $typed"; exit 1; }
done
program=$("$cmbrl" --version | sed -E 's/^cmbrl ([0-9.]+) .*/\1/')
[ "$installed" = "$program" ] || { echo "FAILED: cmbrl.__version__ $installed, cmbrl --version $program"; exit 1; }
# Gymnasium's plugin entry point (group gymnasium.envs) names the function that registers the ids.
"$venv/bin/python" -c "
from importlib.metadata import entry_points
(plugin,) = [p for p in entry_points(group='gymnasium.envs') if p.value.startswith('cmbrl')]
assert (plugin.name, plugin.value) == ('__root__', 'cmbrl.registration:register_envs'), plugin
import cmbrl.registration
assert plugin.load() is cmbrl.registration.register_envs
" || { echo "FAILED: no gymnasium.envs entry point"; exit 1; }
"$venv/bin/python" "$source_dir/examples/gymnasium_loop.py" --num-envs 2 --steps 20 > loop.txt
grep -q "SafetyPointGoal1-v0: one episode" loop.txt
echo "pip install: cmbrl $installed installed into a venv, imported, the example ran"

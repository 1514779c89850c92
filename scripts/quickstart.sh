#!/usr/bin/env bash
# The main job on its defaults, from a fresh Debian 12 machine: installs the dependencies,
# builds, trains the quickstart preset (PointGoal1, RCE, CPU-sized; about 6 minutes on one core)
# and evaluates the trained agent with a top-down picture. Run again, it resumes or re-evaluates.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
bash scripts/build.sh
run=runs/quickstart
if [ -f "$run/config.yaml" ]; then
  ./build/bin/cmbrl train --resume "$run"
else
  ./build/bin/cmbrl train --config configs/pointgoal1-rce.yaml configs/quickstart.yaml --out "$run"
fi
./build/bin/cmbrl eval --run "$run" --episodes 1 --seed 100 --render "$run/eval"
echo "progress: $run/progress.csv   picture: $run/eval/episode-0.png"

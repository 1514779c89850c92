#!/usr/bin/env bash
# The main job on its defaults, from a fresh Debian 12 machine: installs the dependencies,
# builds, runs one random-policy episode of PointGoal1 (the paper's variant) and draws it.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p runs
./build/bin/cmbrl rollout --task PointGoal1 --variant paper --policy random --episodes 1 \
  --seed 0 --render runs/rollout-PointGoal1.png
echo "picture: runs/rollout-PointGoal1.png"

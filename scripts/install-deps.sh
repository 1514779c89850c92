#!/usr/bin/env bash
# Installs every Debian 12 package cmbrl needs to build, test and run. Idempotent: apt-get skips
# what is already installed. Uses sudo only when not run as root.
set -euo pipefail

if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
else
  SUDO=(sudo)
fi

packages=(
  # Toolchain and test/benchmark frameworks.
  build-essential cmake ninja-build ccache pkg-config
  libgtest-dev libgmock-dev libbenchmark-dev
  # Physics: MuJoCo 2.2.2. Its CMake package file also needs qhull and the OpenGL headers.
  libmujoco-dev libqhull-dev libgl-dev
  # Configuration, command line, formatting, JSON, pictures.
  libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev libcairo2-dev
  # Checksums of checkpoint files (CRC-32) and hashes of experiment files (SHA-256).
  zlib1g-dev libssl-dev
  # Learned models: LibTorch (CPU) on OpenBLAS, and XGBoost. XGBoost's CMake package file fails
  # unless the xgboost package (its command-line program) is installed too.
  libtorch-dev libopenblas-dev libxgboost-dev xgboost
  # The fast CPU prediction backend: oneDNN's matrix products (AVX-512, bf16).
  libdnnl-dev
  # A single-node Slurm for the test of `cmbrl sweep --engine slurm`.
  slurm-wlm munge
  # The Python module and its tests.
  pybind11-dev python3-dev python3-numpy python3-pytest python3-pip python3-setuptools python3-wheel python3-venv
  # Checks the type stubs against the module (mypy.stubtest) and the examples against them.
  python3-mypy
)

export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -q
"${SUDO[@]}" apt-get install -y -q --no-install-recommends "${packages[@]}"

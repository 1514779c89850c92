#!/usr/bin/env bash
# The CUDA build and its benchmarks, on a GPU machine that has PyTorch (with its CUDA LibTorch)
# but neither a package registry nor MuJoCo, XGBoost, yaml-cpp and friends (see the GPU machines' notes).
# Two halves:
#
#   bash scripts/gpu-bench.sh fetch     here, on Debian 12 with the package registries: downloads
#                                       the .deb files the GPU machine lacks into gpu-debs/
#                                       (git-ignored; about 40 MB)
#   bash scripts/gpu-bench.sh run [CONFIG...]
#                                       there, with gpu-debs/ carried along: unpacks them into
#                                       build-gpu/deps (never into /), builds against PyTorch's
#                                       LibTorch into build-gpu/, runs bench plan / train / env
#                                       on cuda for each config (default: the PointGoal1 paper
#                                       presets and the quickstart), prints a table, then trains
#                                       the quickstart for 300 steps there (train_smoke).
#   bash scripts/gpu-bench.sh build     there: builds as `run` does, and stops when the program
#                                       binds a standard-library function into LibTorch.
#   bash scripts/gpu-bench.sh smoke     there: builds, then only the training run (train_smoke),
#                                       with cuda-gdb's stack if it fails.
#   bash scripts/gpu-bench.sh plan [CONFIG]
#                                       there: builds, then only `bench plan` for RCE, CEM and
#                                       random (default: the PointGoal2 RCE paper preset); on CUDA
#                                       its lines name the trees' path, the tensor operations'
#                                       time beside the kernel's, and whether the kernel gave the
#                                       host's bits.
#   bash scripts/gpu-bench.sh checks [SECONDS]
#                                       there: one build, then smoke, plan and paper SECONDS
#                                       (default 300) in turn, each run even if one before failed;
#                                       logs to $OUT (the device tool's) or build-gpu/.
#   bash scripts/gpu-bench.sh paper [SECONDS]
#                                       there: builds as `run` does, then trains PointGoal2 RCE
#                                       at the paper's size for at most SECONDS (resumable).
#
# Without a usable CUDA PyTorch, `run` builds against the system's LibTorch and measures the
# CPU, so the script can be checked on any machine.
set -euo pipefail
cd "$(dirname "$0")/.."

debs_dir=gpu-debs
deps_dir=build-gpu/deps

# What cmbrl links and the GPU machine lacks, with the libraries they load.
packages=(
  libmujoco2.2.2 libmujoco-dev libccd2 liblodepng0 libqhull-r8.0 libqhull-dev libqhull8.0
  libqhullcpp8.0 libtinyxml2-9 libxgboost0 libxgboost-dev libdmlc0 libdmlc-dev xgboost
  libyaml-cpp0.7 libyaml-cpp-dev libfmt9 libfmt-dev nlohmann-json3-dev libcli11-dev
  pkgconf pkgconf-bin libpkgconf3
)
# Cairo and everything its development package needs (pkg-config resolves all of it).
cairo_root=libcairo2-dev

fetch() {
  mkdir -p "$debs_dir"
  local closure
  closure=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts \
    --no-breaks --no-replaces --no-enhances "$cairo_root" | grep '^[a-z0-9]' | sort -u)
  # Packages of the base system every machine has in a newer version, and what only programs
  # and documents need (fonts, interpreters): never carried.
  closure=$(grep -v -E '^(fonts-.*|python3.*|libpython3.*|libdb5.3|libsqlite3-0|libglib2.0-data|libglib2.0-bin|libc6|libc6-dev|libc-dev-bin|linux-libc-dev|libgcc-s1|libstdc\+\+6|gcc-[0-9]+-base|libcrypt1|libcrypt-dev|libnsl.*|libtirpc.*|rpcsvc-proto|debconf.*|dpkg|perl.*|tar|install-info|zlib1g|libzstd1|liblzma5|libbz2-1.0|libgssapi.*|libkrb5.*|libk5crypto3|libkeyutils1|libcom-err2|libssl3)$' <<<"$closure")
  (cd "$debs_dir" && apt-get download "${packages[@]}" $closure)
  echo "fetched $(ls "$debs_dir"/*.deb | wc -l) packages ($(du -sh "$debs_dir" | cut -f1)) into $debs_dir/"
}

# Unpacks the carried packages, builds into build-gpu/ (again only what changed) and sets
# `device`: cuda where PyTorch sees a GPU, else cpu against the system's LibTorch.
device=cpu
build() {
  [ -d "$debs_dir" ] || { echo "no $debs_dir/: run 'bash scripts/gpu-bench.sh fetch' on a Debian 12 machine and carry it" >&2; exit 2; }
  mkdir -p "$deps_dir"
  for deb in "$debs_dir"/*.deb; do dpkg-deb -x "$deb" "$deps_dir"; done
  # The machine's own C and C++ runtime must win over anything a package brought along.
  find "$deps_dir" \( -name 'libc.so*' -o -name 'libm.so*' -o -name 'libstdc++.so*' \
    -o -name 'libgcc_s.so*' -o -name 'ld-linux*' -o -name 'libpthread.so*' \) -delete
  local prefix multiarch
  prefix=$(cd "$deps_dir/usr" && pwd)
  multiarch=$prefix/lib/x86_64-linux-gnu
  # Package files name their own prefix as /usr: point pkg-config and the libraries' symlinks
  # at the unpacked tree.
  export PKG_CONFIG_LIBDIR="$multiarch/pkgconfig:$prefix/share/pkgconfig"
  export PKG_CONFIG_SYSROOT_DIR="$(cd "$deps_dir" && pwd)"
  export LD_LIBRARY_PATH="$multiarch${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  command -v pkg-config >/dev/null || export PATH="$prefix/bin:$PATH"
  for link in "$multiarch"/*.so; do
    target=$(readlink "$link" || true)
    case "$target" in /*) ln -sf "$deps_dir/..${target#/usr}" "$link" 2>/dev/null || true ;; esac
  done

  local torch_prefix=""
  if torch_prefix=$(python3 -c 'import torch; print(torch.utils.cmake_prefix_path)' 2>/dev/null) &&
     python3 -c 'import torch, sys; sys.exit(0 if torch.cuda.is_available() else 1)' 2>/dev/null; then
    device=cuda
  else
    echo "no CUDA PyTorch here: building against the system LibTorch and measuring the CPU" >&2
    torch_prefix=""
  fi
  local configure=(cmake -S . -B build-gpu -DCMAKE_BUILD_TYPE=Release -DCMBRL_BUILD_TESTS=OFF
    -DCMBRL_BUILD_BENCHMARKS=OFF -DCMBRL_BUILD_PYTHON=OFF -DCMBRL_WARNINGS_AS_ERRORS=OFF
    "-DCMAKE_PREFIX_PATH=${torch_prefix:+$torch_prefix;}$prefix")
  # With Ninja, every error at once (-k 0): a newer LibTorch may break several files. If the
  # build with cmbrl's own CUDA kernels fails (their first builds there), the errors stay above
  # and the program is built again without them, so the lent minutes still measure the rest.
  local keep_going=""
  if command -v ninja >/dev/null; then
    configure+=(-G Ninja)
    keep_going="-k 0"
  fi
  if ! { "${configure[@]}" -DCMBRL_WITH_CUDA_KERNELS=ON &&
         cmake --build build-gpu --parallel "$(nproc)" -- $keep_going; }; then
    echo "the build with cmbrl's CUDA kernels failed (errors above): building without them" >&2
    "${configure[@]}" -DCMBRL_WITH_CUDA_KERNELS=OFF
    cmake --build build-gpu --parallel "$(nproc)" -- $keep_going
  fi
  # The standard library's functions must bind to the system's libstdc++, not to the copies
  # PyTorch's LibTorch exports (cmake/CmbrlDependencies.cmake): name any that bind into LibTorch.
  local stray
  stray=$(LD_BIND_NOW=1 LD_DEBUG=bindings build-gpu/bin/cmbrl --version 2>&1 |
    grep 'binding file build-gpu/bin/cmbrl .* to .*libtorch' | grep -o 'symbol `_ZNSt[^'"'"']*' |
    sort -u || true)
  if [ -n "$stray" ]; then
    echo "bin/cmbrl binds $(grep -c . <<<"$stray") standard-library symbols into LibTorch" \
      "(its remove_all crashes the second checkpoint):" >&2
    echo "$stray" >&2
    exit 1
  fi
  echo "bin/cmbrl binds no standard-library symbol into LibTorch"
}

run() {
  build
  local configs=("$@")
  [ ${#configs[@]} -gt 0 ] || configs=(configs/pointgoal1-rce.yaml)
  local results=build-gpu/bench.jsonl
  : >"$results"
  for config in "${configs[@]}"; do
    build-gpu/bin/cmbrl bench plan --config "$config" --device "$device" \
      --planners rce cem random --runs 20 | tee -a "$results"
    if [ "$device" = cuda ]; then
      build-gpu/bin/cmbrl bench plan --config "$config" --device cuda --planners rce \
        --precisions fp32 tf32 bf16 --runs 20 | tee -a "$results"
    fi
    build-gpu/bin/cmbrl bench train --config "$config" --device "$device" --full-fit --runs 3 |
      tee -a "$results"
  done
  build-gpu/bin/cmbrl bench env --config "${configs[0]}" --runs 5 | tee -a "$results"
  # The JSON lines as one Markdown table.
  python3 - "$results" << 'PY'
import json, sys
lines = [json.loads(t) for t in open(sys.argv[1]) if t.strip().startswith("{")]
for line in lines:
    if line.get("bench") == "ceiling":
        rates = ", ".join(f"{k} {v:.0f}" for k, v in line.items() if k.endswith("_gflops"))
        print(f'ceiling on {line["device"]}: GEMM GFLOP/s {rates}')
print("| what | median | floor | ratio |\n|---|---|---|---|")
for line in lines:
    if "median_ms" not in line:
        continue
    name = " ".join(str(line[k]) for k in ("task", "what", "planner", "precision") if line.get(k))
    floor = f'{line["floor_ms"]:.2f} ms' if "floor_ms" in line else ""
    ratio = f'{line["ratio_to_ceiling"]:.2f}' if "ratio_to_ceiling" in line else ""
    print(f'| {name} | {line["median_ms"]:.2f} ms | {floor} | {ratio} |')
PY
  train_smoke "$device"
}

# The episodes a run folder's progress.csv holds (0 when it has none).
episodes_logged() { tail -n +2 "$1/progress.csv" 2>/dev/null | wc -l; }

# A short training run on the device (the quickstart, 300 agent steps: pre-training, a fit and
# three episodes with their checkpoints). On CUDA the first such run (2026-11-27) died of a call
# through a null function pointer after its first episode; if it fails again, the same run
# under cuda-gdb prints the stack and the caller's return address (a call to address 0 leaves
# no frame to unwind, but the address it would return to is on top of the stack).
train_smoke() {
  local device=$1 out=build-gpu/train-smoke
  local run=(build-gpu/bin/cmbrl train --config configs/pointgoal1-rce.yaml configs/quickstart.yaml
             --device "$device" --steps 300)
  rm -rf "$out" "$out-gdb"
  if "${run[@]}" --out "$out"; then
    echo "train smoke on $device: passed ($(episodes_logged "$out") episodes)"
    return
  fi
  echo "train smoke on $device: FAILED" >&2
  # Where it died: the rows it logged and the steps its last checkpoint holds (a run whose
  # checkpoint holds its whole budget died on the way out, not in an episode or a fit).
  local held
  held=$(grep -o '"steps_done": *[0-9]*' "$out/checkpoint/manifest.json" 2>/dev/null || echo none)
  echo "episodes logged: $(episodes_logged "$out"); its last checkpoint's $held" \
    "(the budget: 300)" >&2
  if command -v cuda-gdb >/dev/null; then
    # After a call to address 0 the return address is on top of the stack: popping it into the
    # program counter puts the caller back, and the stack unwinds from there.
    cuda-gdb -q -batch -ex run -ex bt -ex 'info registers rip rsp' -ex 'x/a $sp' \
      -ex 'info symbol *(void**)$sp' -ex 'set $pc = *(void **)$sp' -ex 'set $sp = $sp + 8' \
      -ex 'bt 40' --args "${run[@]}" --out "$out-gdb" 2>&1 |
      grep -v -E '^\[(New|Thread|Detaching)' | tail -n 60 || true
  fi
  return 1
}

# `bench plan` alone for RCE, CEM and random at CONFIG (default: the PointGoal2 RCE paper preset).
plan_bench() {
  build-gpu/bin/cmbrl bench plan --config "${1:-configs/pointgoal2-rce.yaml}" --device "$device" \
    --planners rce cem random --runs 10
}

# One run of experiments/paper-size's protocol on the device (issue 56 item 4): PointGoal2 RCE
# at the paper's preset, seed 0, the first 3000 agent steps, within SECONDS (default 420) of
# training; stopped there by SIGTERM it checkpoints, and the same command resumes it while the
# machine is kept. Its logs go to $OUT when the device tool gives one (else build-gpu/).
paper() {
  [ "${built:-}" = yes ] || build
  if [ "$device" != cuda ]; then
    echo "paper: no GPU here (the CPU's runs are experiments/paper-size's)" >&2
    exit 2
  fi
  local seconds=${1:-420} out=build-gpu/paper-pointgoal2-rce-s0 logs=${OUT:-build-gpu}/paper-run
  local status=0
  if [ -f "$out/checkpoint/manifest.json" ]; then
    timeout -s TERM "$seconds" build-gpu/bin/cmbrl train --resume "$out" || status=$?
  else
    rm -rf "$out"
    timeout -s TERM "$seconds" build-gpu/bin/cmbrl train --config configs/pointgoal2-rce.yaml \
      --set training.total_steps=3000 --seed 0 --device cuda --out "$out" || status=$?
  fi
  mkdir -p "$logs"
  cp "$out"/config.yaml "$out"/progress.csv "$out"/sessions.jsonl "$logs"/ 2>/dev/null || true
  echo "paper run: exit $status (124: stopped at ${seconds} s), $(episodes_logged "$out")" \
    "episodes logged; logs in $logs"
  return "$status"
}

case "${1:-}" in
  fetch) fetch ;;
  build) build ;;
  smoke) build; train_smoke "$device" ;;
  run) shift; run "$@" ;;
  plan) build; plan_bench "${2:-}" ;;
  paper) shift; paper "$@" ;;
  checks)
    # One build, then the training smoke, the plan bench and the paper run (SECONDS, default
    # 300), each reported even when an earlier one failed; the logs go to $OUT when given.
    build; built=yes; logs=${OUT:-build-gpu}; status=0
    train_smoke "$device" > "$logs/smoke.log" 2>&1 || status=1
    tail -n 3 "$logs/smoke.log"
    plan_bench > "$logs/plan.jsonl" 2> "$logs/plan.err" || status=1
    grep -o '"planner":"[a-z]*"\|"median_ms":[0-9.]*\|"classifier_[a-z_]*":[^,}]*' \
      "$logs/plan.jsonl" | paste -sd' ' || true
    paper "${2:-300}" || status=1
    exit "$status" ;;
  *) echo "usage: bash scripts/gpu-bench.sh fetch | build | smoke | run [CONFIG...] | plan [CONFIG] | paper [SECONDS] | checks [SECONDS]" >&2; exit 2 ;;
esac

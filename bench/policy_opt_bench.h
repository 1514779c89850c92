// `cmbrl bench learn`: epochs of a model-free baseline at a config's settings, split into the
// rollout (against bare physics of as many steps), the trust-region step, and the value fits
// (against their floor at the matrix-product ceiling measured in the same run). Benchmarks give
// figures; nothing here judges them.
#pragma once

#include <cstdint>
#include <string>

#include "bench/bench_util.h"

namespace cmbrl::bench {

struct PolicyOptBenchOptions {
  std::string config_path = "configs/pointgoal1-trpo-lagrangian.yaml";
  int runs = 3;                  // epochs timed, after one warm-up epoch
  std::int64_t steps = 30000;    // environment steps an epoch (the config's otherwise)
  int envs = 0;                  // 0: the config's
  std::uint64_t seed = 0;
};

void RunPolicyOptBench(const PolicyOptBenchOptions& options, const FigureSink& emit);

}  // namespace cmbrl::bench

// `cmbrl bench env`: agent steps per second of a random policy per task and variant, beside
// the bare physics ceiling measured in the same run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/bench_util.h"
#include "cmbrl/env/registry.h"

namespace cmbrl::bench {

struct EnvBenchOptions {
  std::vector<std::string> tasks = PaperEnvNames();
  std::vector<std::string> variants = {"paper", "standard"};
  int steps = 2000;  // agent steps per run
  int runs = 5;
  std::uint64_t seed = 0;
  std::string device = "cpu";
  std::string config_path;  // when set, its task and variant replace tasks and variants
};

// The ceiling of an env benchmark: bare mj_step calls on the same compiled model, from the same
// start and with the same kind of random controls, as many per agent step as the environment
// runs. Returns agent steps per second at that rate.
double PhysicsCeiling(const std::string& task, Variant variant, std::uint64_t seed, int steps);

// Agent steps of a random policy per wall-clock second, resets included, per task and variant.
void RunEnvBench(EnvBenchOptions options, const FigureSink& emit);

}  // namespace cmbrl::bench

#include "bench/policy_opt_bench.h"

#include <torch/torch.h>

#include <nlohmann/json.hpp>

#include "bench/ceiling.h"
#include "bench/env_throughput.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/config/config.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

namespace cmbrl::bench {

void RunPolicyOptBench(const PolicyOptBenchOptions& options, const FigureSink& emit) {
  TrainConfig config = LoadTrainConfig(options.config_path);
  Require(&FamilyOf(config.algorithm) == &PolicyOptFamily(),
          "'{}' is an MPC config: bench learn measures the model-free algorithms (bench plan "
          "and bench train measure MPC)",
          options.config_path);
  config.seed = options.seed;
  config.policy_optimisation.steps_per_epoch = options.steps;
  if (options.envs > 0) config.policy_optimisation.envs = options.envs;
  config.training.total_steps = options.steps * (options.runs + 1);
  ValidateTrainConfig(config, options.config_path);
  const torch::Device cpu(torch::kCPU);
  GemmCeilings(cpu, options.runs, emit);
  CeilingProbe probe(cpu, "fp32");
  PolicyOptLearner learner(config);
  UnitContext whole_epochs;
  whole_epochs.elapsed_seconds = [] { return 0.0; };
  whole_epochs.cpu_seconds = [] { return 0.0; };
  learner.Advance(whole_epochs);  // warm-up
  std::vector<double> epochs, rollouts, updates, values, ceilings, physics;
  for (int run = 0; run < options.runs; ++run) {
    ceilings.push_back(probe.Measure());
    physics.push_back(PhysicsCeiling(config.task, config.variant, DeriveSeed(options.seed, run),
                                     static_cast<int>(std::min<std::int64_t>(options.steps,
                                                                             5000))));
    learner.Advance(whole_epochs);
    const PolicyOptLearner::Timings& t = learner.last_timings();
    rollouts.push_back(t.rollout);
    updates.push_back(t.policy_update);
    values.push_back(t.value_fits);
    epochs.push_back(t.rollout + t.policy_update + t.value_fits);
  }
  const double flops = learner.ValueFitFlops(options.steps);
  const double ceiling = Median(ceilings);
  const double epoch = Median(epochs);
  const double rollout = Median(rollouts);
  nlohmann::ordered_json line = {
      {"bench", "learn"},
      {"what", "epoch"},
      {"task", config.task},
      {"algorithm", config.algorithm},
      {"steps", options.steps},
      {"envs", config.policy_optimisation.envs},
      {"runs", options.runs},
      {"epoch_s", epoch},
      {"rollout_s", rollout},
      {"rollout_steps_per_second", static_cast<double>(options.steps) / rollout},
      {"physics_ceiling_steps_per_second", Median(physics)},
      {"rollout_ratio_to_physics", static_cast<double>(options.steps) / rollout / Median(physics)},
      {"policy_update_s", Median(updates)},
      {"value_fits_s", Median(values)},
      {"value_fit_gflop", flops / 1e9},
      {"ceiling_gflops", ceiling / 1e9},
      {"value_fit_floor_s", flops / ceiling},
      {"value_fit_ratio_to_ceiling", flops / Median(values) / ceiling},
      {"hours_for_1e7_steps", epoch * 1e7 / static_cast<double>(options.steps) / 3600.0},
  };
  emit(line);
}

}  // namespace cmbrl::bench

#include "bench/env_throughput.h"

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>

#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/env/navigation_env.h"
#include "cmbrl/config/config.h"

namespace cmbrl::bench {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

double PhysicsCeiling(const std::string& task, Variant variant, std::uint64_t seed, int steps) {
  NavigationEnv env(NavigationTaskSpecByName(task, variant));
  env.Reset(seed);
  const mjModel& model = env.model();
  MjDataPtr data = MakeMjData(model);
  mj_copyData(data.get(), &model, &env.data());
  RandomPolicy policy(env.action_spec(), seed);
  const int frames = env.spec().frame_skip * env.spec().action_repeat;
  const auto start = Clock::now();
  for (int step = 0; step < steps; ++step) {
    const std::vector<double> action = policy.Act({});
    for (int i = 0; i < model.nu; ++i) {
      data->ctrl[i] = std::clamp(action[i], model.actuator_ctrlrange[2 * i],
                                 model.actuator_ctrlrange[2 * i + 1]);
    }
    for (int frame = 0; frame < frames; ++frame) mj_step(&model, data.get());
  }
  const std::chrono::duration<double> elapsed = Clock::now() - start;
  return steps / elapsed.count();
}

// Agent steps of a random policy per wall-clock second, resets included, beside the bare
// physics ceiling measured in the same run.
void RunEnvBench(EnvBenchOptions args, const FigureSink& emit) {
  if (!args.config_path.empty()) {
    const TrainConfig config = LoadTrainConfig(args.config_path);
    args.tasks = {config.task};
    args.variants = {VariantName(config.variant)};
  }
  for (const std::string& variant_name : args.variants) {
    const Variant variant = ParseVariant(variant_name);
    for (const std::string& task : args.tasks) {
      std::unique_ptr<Env> env = MakeEnv(task, variant);
      RandomPolicy policy(env->action_spec(), DeriveSeed(args.seed, 1));
      std::vector<double> rates, ceilings;
      int env_steps = 0;
      for (int run = 0; run < args.runs; ++run) {
        ceilings.push_back(
            PhysicsCeiling(task, variant, DeriveSeed(args.seed, 100 + run), args.steps));
        std::vector<double> observation = env->Reset(DeriveSeed(args.seed, 100 + run));
        env_steps = 0;
        const auto start = Clock::now();
        for (int step = 0; step < args.steps; ++step) {
          StepResult result = env->Step(policy.Act(observation));
          env_steps += result.info.env_steps;
          observation =
              result.terminated || result.truncated ? env->Reset() : std::move(result.observation);
        }
        const std::chrono::duration<double> elapsed = Clock::now() - start;
        rates.push_back(args.steps / elapsed.count());
      }
      const double median = Median(rates);
      const double ceiling = Median(ceilings);
      const nlohmann::ordered_json line = {
          {"bench", "env"},
          {"task", task},
          {"variant", variant_name},
          {"device", "cpu"},
          {"agent_steps_per_second", median},
          {"env_steps_per_second", median * env_steps / args.steps},
          {"min_agent_steps_per_second", *std::min_element(rates.begin(), rates.end())},
          {"max_agent_steps_per_second", *std::max_element(rates.begin(), rates.end())},
          {"ceiling_agent_steps_per_second", ceiling},
          {"ratio_to_ceiling", median / ceiling},
          {"agent_step_sim_seconds", env->agent_step_seconds()},
          {"realtime_factor", median * env->agent_step_seconds()},
          {"steps_per_run", args.steps},
          {"runs", args.runs},
      };
      emit(line);
    }
  }
}


}  // namespace cmbrl::bench

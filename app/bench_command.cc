// `cmbrl bench ...`: the benchmarks of bench/ with their options; each figure printed as one
// JSON line (median of several runs). Benchmarks print figures; nothing here judges them.
#include <fmt/ranges.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/arguments.h"
#include "app/commands.h"
#include "bench/env_throughput.h"
#include "bench/learning_bench.h"
#include "bench/policy_opt_bench.h"
#include "cmbrl/planning/planner_registry.h"

namespace cmbrl::app {
namespace {

void PrintFigure(const nlohmann::ordered_json& line) { std::cout << line.dump() << std::endl; }

void AddCommonOptions(CLI::App& command, bench::LearningBenchOptions& args) {
  command.add_option("--config", args.config_paths,
                     "training config files (YAML) whose settings to use, composed in order "
                     "(a task's preset, then a family such as configs/cpu.yaml)")
      ->check(ExistingFile())
      ->capture_default_str();
  command.add_option("--device", args.device, "cpu, cuda or cuda:N (default: the config's)");
  command.add_option("--runs", args.runs, "runs per figure; the median is reported")
      ->check(IntegerIn(1, 1000))
      ->capture_default_str();
  command.add_option("--seed", args.seed, "seed")->check(SeedInteger())->capture_default_str();
}

void AddBenchLearningCommands(CLI::App& bench_command) {
  auto plan_args = std::make_shared<bench::LearningBenchOptions>();
  CLI::App* plan = bench_command.add_subcommand(
      "plan",
      "Time of one MPC planning step (the action's copy to the host included) at a config's "
      "settings, with its dynamics and classifier parts, beside the matrix-product floor");
  AddCommonOptions(*plan, *plan_args);
  plan->add_option("--planners", plan_args->planners,
                   fmt::format("{} (default: the config's)", fmt::join(PlannerNames(), ", ")))
      ->check(CLI::IsMember(PlannerNames()));
  plan->add_option("--precisions", plan_args->precisions,
                   "fp32, tf32 (CUDA), bf16 (default: the config's); with several, the models are "
                   "first fitted briefly and each later precision's prediction errors and chosen "
                   "actions are compared with the first's")
      ->check(CLI::IsMember({"fp32", "tf32", "bf16"}));
  plan->add_option("--backends", plan_args->backends,
                   "auto, libtorch, onednn (default: the config's); crossed with --precisions, the "
                   "first pair being the reference")
      ->check(CLI::IsMember({"auto", "libtorch", "onednn"}));
  plan->add_option("--fit-steps", plan_args->fit_steps,
                   "random-policy transitions of that fit")
      ->check(IntegerIn(1, 100'000'000))
      ->capture_default_str();
  plan->add_option("--agreement-states", plan_args->agreement_states,
                   "start states whose chosen actions are compared")
      ->check(IntegerIn(1, 100'000))
      ->capture_default_str();
  plan->callback([plan_args] { bench::RunPlanBench(*plan_args, PrintFigure); });

  auto train_args = std::make_shared<bench::LearningBenchOptions>();
  train_args->runs = 3;
  CLI::App* train = bench_command.add_subcommand(
      "train",
      "Time of one dynamics training epoch, of its optimiser step and of a classifier fit at a "
      "config's settings, beside the matrix-product floor and the memory's");
  AddCommonOptions(*train, *train_args);
  train->add_option("--transitions", train_args->transitions, "transitions of the epoch")
      ->check(IntegerIn(1, 100'000'000))
      ->capture_default_str();
  train->add_option("--classifier-states", train_args->classifier_states,
                    "states of the classifier fit")
      ->check(IntegerIn(4, 1 << 30))
      ->capture_default_str();
  train->add_option("--backends", train_args->backends,
                    "auto, libtorch, onednn (default: the config's); each times the same epoch, "
                    "the backends alternating run by run")
      ->check(CLI::IsMember({"auto", "libtorch", "onednn"}));
  train->add_flag("--full-fit", train_args->full_fit,
                  "also time one whole fit, up to the config's max_epochs");
  train->callback([train_args] { bench::RunTrainBench(*train_args, PrintFigure); });
}

}  // namespace

void AddBenchCommand(CLI::App& parent) {
  CLI::App* bench_command =
      parent.add_subcommand("bench", "Measure speed; print one JSON line per measurement");
  bench_command->require_subcommand(1);

  auto env_args = std::make_shared<bench::EnvBenchOptions>();
  CLI::App* env = bench_command->add_subcommand(
      "env", "Agent steps per second of a random policy, per task and variant (median of runs)");
  env->add_option("--tasks", env_args->tasks, "tasks to measure")->capture_default_str();
  env->add_option("--variants", env_args->variants, "paper and/or standard")->capture_default_str();
  env->add_option("--steps", env_args->steps, "agent steps per run")
      ->check(IntegerIn(1, 100'000'000))
      ->capture_default_str();
  env->add_option("--runs", env_args->runs, "runs; the median is reported")
      ->check(IntegerIn(1, 1000))
      ->capture_default_str();
  env->add_option("--seed", env_args->seed, "seed")->check(SeedInteger())->capture_default_str();
  env->add_option("--config", env_args->config_path,
                  "training config (YAML): measure its task and variant only")
      ->check(ExistingFile());
  env->add_option("--device", env_args->device,
                  "accepted for symmetry with bench plan and train: MuJoCo simulates on the CPU")
      ->check(CLI::IsMember({"cpu", "cuda"}));
  env->callback([env_args] { bench::RunEnvBench(*env_args, PrintFigure); });

  AddBenchLearningCommands(*bench_command);

  auto learn_args = std::make_shared<bench::PolicyOptBenchOptions>();
  CLI::App* learn = bench_command->add_subcommand(
      "learn",
      "Epochs of a model-free baseline (TRPO, TRPO-Lagrangian, CPO) at a config's settings: the "
      "rollout beside bare physics, the trust-region step, the value fits beside their GEMM "
      "floor");
  learn->add_option("--config", learn_args->config_path, "model-free config (YAML)")
      ->check(ExistingFile())
      ->capture_default_str();
  learn->add_option("--runs", learn_args->runs, "epochs timed after a warm-up; the median is "
                    "reported")
      ->check(IntegerIn(1, 1000))
      ->capture_default_str();
  learn->add_option("--steps", learn_args->steps, "environment steps an epoch")
      ->check(IntegerIn(1, 100'000'000))
      ->capture_default_str();
  learn->add_option("--envs", learn_args->envs, "environments side by side (default: the "
                    "config's)")
      ->check(IntegerIn(1, 1024));
  learn->add_option("--seed", learn_args->seed, "seed")->check(SeedInteger())->capture_default_str();
  learn->callback([learn_args] { bench::RunPolicyOptBench(*learn_args, PrintFigure); });
}

}  // namespace cmbrl::app

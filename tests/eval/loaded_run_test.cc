#include "cmbrl/eval/loaded_run.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "cmbrl/agent/policy.h"
#include "cmbrl/env/env.h"
#include "cmbrl/train/trainer.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;

// The first actions a loaded run takes from a seeded reset.
std::vector<std::vector<double>> FirstActions(const std::string& dir) {
  LoadedRun run(dir, 3);
  std::vector<double> observation = run.env().Reset(11);
  run.policy().BeginEpisode();
  std::vector<std::vector<double>> actions;
  for (int step = 0; step < 3; ++step) {
    actions.push_back(run.policy().Act(observation));
    observation = run.env().Step(actions.back()).observation;
  }
  return actions;
}

// A stop between a checkpoint's two renames leaves only checkpoint.old: a loaded run reads it in
// place, as --resume would recover it, and acts the same; it renames nothing.
TEST(LoadedRunTest, OnlyCheckpointOldLeftIsReadInPlace) {
  const std::vector<std::string> configs = {
      "task: PointGoal1\nalgorithm: mpc\ntraining: {pretrain_episodes: 2, pretrain_steps: 5, "
      "total_steps: 20}\nensemble: {hidden_sizes: [8]}\nclassifier: {rounds: 2}\nplanning: "
      "{population: 12, elites: 4, min_feasible_elites: 2, max_iterations: 1, random_samples: 8, "
      "horizon: 2}\n",
      "task: PointGoal1\nvariant: paper-lidar\nalgorithm: trpo\ntraining: {total_steps: 600}\n"
      "policy_optimisation: {steps_per_epoch: 300, envs: 1, env_threads: 1, policy_hidden: [8], "
      "value_hidden: [8]}\n"};
  for (size_t i = 0; i < configs.size(); ++i) {
    SCOPED_TRACE(configs[i]);
    const fs::path dir = testing::TestTempPath("loaded_run_" + std::to_string(i));
    fs::remove_all(dir);
    Trainer::Start(ParseTrainConfig(configs[i], "loaded run test"), dir.string())->Run();
    const std::vector<std::vector<double>> whole = FirstActions(dir.string());
    fs::rename(dir / "checkpoint", dir / "checkpoint.old");
    EXPECT_EQ(FirstActions(dir.string()), whole);
    EXPECT_FALSE(fs::exists(dir / "checkpoint"));
    EXPECT_TRUE(fs::exists(dir / "checkpoint.old"));
    fs::remove_all(dir);
  }
}

// Overrides change how a trained planner plans: a model-free run, which has none, refuses them
// by name instead of ignoring them; an MPC run takes them, and still refuses the model keys.
TEST(LoadedRunTest, OverridesThatDoNotApplyToTheRunsFamilyAreRefused) {
  const fs::path dir = testing::TestTempPath("loaded_run_overrides");
  fs::remove_all(dir);
  Trainer::Start(ParseTrainConfig("task: PointGoal1\nvariant: paper-lidar\nalgorithm: trpo\n"
                                  "training: {total_steps: 300}\npolicy_optimisation: "
                                  "{steps_per_epoch: 300, envs: 1, env_threads: 1, "
                                  "policy_hidden: [8], value_hidden: [8]}\n",
                                  "overrides test"),
                 dir.string())
      ->Run();
  for (const std::string item :
       {"planning.population=50", "objective.gamma=0.9", "classifier.threshold=0.3", "planner=cem"}) {
    SCOPED_TRACE(item);
    EXPECT_THAT(testing::ErrorMessage([&] { LoadedRun(dir.string(), 0, {item}); }),
                ::testing::HasSubstr(fmt::format(
                    "override '{}': a policy optimisation run (trpo) has no planner", item)));
  }
  EXPECT_THAT(testing::ErrorMessage([&] { LoadedRun(dir.string(), 0, {"ensemble.max_epochs=3"}); }),
              ::testing::HasSubstr("can change for a trained run"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cmbrl

// The model-free learner's checkpoint (learners/policy_opt/policy_opt_checkpoint.cc). Whole runs
// stopped and resumed at every point of an epoch, and damaged checkpoints, are tested through the
// trainer (tests/train/trainer_test.cc).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "cmbrl/env/registry.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

TrainConfig TinyTrpoConfig() {
  return ParseTrainConfig(
      "task: PointGoal1\nvariant: paper-lidar\nalgorithm: trpo-lagrangian\n"
      "training: {total_steps: 600}\npolicy_optimisation: {steps_per_epoch: 300, envs: 2, "
      "env_threads: 1, policy_hidden: [8], value_hidden: [8]}\n",
      "policy_opt learner test");
}

// A checkpoint's policy, loaded alone, acts as the trained learner's own policy does.
TEST(PolicyOptCheckpointTest, ThePolicyLoadedAloneActsAsTheLearnersPolicy) {
  const TrainConfig config = TinyTrpoConfig();
  PolicyOptLearner learner(config);
  UnitContext context;
  context.elapsed_seconds = [] { return 0.0; };
  context.cpu_seconds = [] { return 0.0; };
  while (!learner.Finished()) learner.Advance(context);
  const std::filesystem::path folder = testing::TestTempPath("policy_opt_checkpoint");
  std::filesystem::create_directories(folder);
  learner.Save(folder, {}, /*models_changed=*/true);

  const std::unique_ptr<Env> env = MakeEnv(config.task, config.variant, config.spawn);
  GaussianMeanPolicy trained(learner.policy(), env->action_spec());
  const std::unique_ptr<GaussianMeanPolicy> loaded =
      LoadPolicyOptMeanPolicy(config, folder, env->observation_spec().size(), env->action_spec());
  std::vector<double> observation = env->Reset(5);
  for (int step = 0; step < 20; ++step) {
    const std::vector<double> action = trained.Act(observation);
    EXPECT_EQ(loaded->Act(observation), action);
    observation = env->Step(action).observation;
  }

  // A config of other network sizes does not fit the file, and says so.
  TrainConfig other = config;
  other.policy_optimisation.policy_hidden = {16};
  EXPECT_THAT(testing::ErrorMessage([&] {
                LoadPolicyOptMeanPolicy(other, folder, env->observation_spec().size(),
                                        env->action_spec());
              }),
              ::testing::HasSubstr("does not hold this run's networks"));
  EXPECT_THAT(testing::ErrorMessage([&] {
                LoadPolicyOptMeanPolicy(config, folder / "missing", env->observation_spec().size(),
                                        env->action_spec());
              }),
              ::testing::HasSubstr("could not read the networks from"));
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace cmbrl

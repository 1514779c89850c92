#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

#include <dlfcn.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cmbrl/env/registry.h"
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
TEST(PolicyOptLearnerTest, ThePolicyLoadedAloneActsAsTheLearnersPolicy) {
  const TrainConfig config = TinyTrpoConfig();
  PolicyOptLearner learner(config);
  UnitContext context;
  context.elapsed_seconds = [] { return 0.0; };
  while (!learner.Finished()) learner.Advance(context);
  const std::filesystem::path folder = testing::TestTempPath("policy_opt_checkpoint");
  std::filesystem::create_directories(folder);
  learner.Save(folder, {}, /*models_changed=*/true);

  const std::unique_ptr<Env> env = MakeEnv(config.task, config.variant, config.spawn);
  GaussianMeanPolicy trained(learner.policy(), env->action_spec());
  const std::unique_ptr<GaussianMeanPolicy> loaded = LoadPolicyOptMeanPolicy(
      config, folder, env->observation_spec().size(), env->action_spec());
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
                LoadPolicyOptMeanPolicy(config, folder / "missing",
                                        env->observation_spec().size(), env->action_spec());
              }),
              ::testing::HasSubstr("could not read the networks from"));
  std::filesystem::remove_all(folder);
}

// An epoch's numbers do not depend on how many threads LibTorch may use: a run on 2 cores gives
// the rows of a run on 1 (before the epoch's math was kept on one thread, the first epoch's KL
// already differed). The paper's networks, 6000 steps over 20 environments: sizes at which it
// did (smaller ones did not show it).
TEST(PolicyOptLearnerTest, TheRowsDoNotDependOnLibTorchsThreadCount) {
  const TrainConfig config = ParseTrainConfig(
      "task: PointGoal1\nvariant: paper-lidar\nalgorithm: trpo-lagrangian\n"
      "training: {total_steps: 6000}\npolicy_optimisation: {steps_per_epoch: 6000, envs: 20, "
      "env_threads: 2, value_iterations: 2}\n",
      "policy_opt learner test");
  // LibTorch's own threads and OpenBLAS's (looked up as the program does, when it has them).
  using SetThreads = void (*)(int);
  const auto blas_set_threads =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  const auto set_threads = [&](int threads) {
    at::set_num_threads(threads);
    if (blas_set_threads != nullptr) blas_set_threads(threads);
  };
  const int threads_before = at::get_num_threads();
  const auto rows_with_threads = [&](int threads) {
    set_threads(threads);
    PolicyOptLearner learner(config);
    UnitContext context;
    context.elapsed_seconds = [] { return 0.0; };
    std::vector<std::string> rows;
    while (!learner.Finished()) {
      const LearnerStep step = learner.Advance(context);
      if (step.row) rows.push_back(*step.row);
    }
    EXPECT_EQ(at::get_num_threads(), threads);  // the epoch restores the count it found
    return rows;
  };
  const std::vector<std::string> one = rows_with_threads(1);
  const std::vector<std::string> four = rows_with_threads(4);
  set_threads(threads_before);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one, four);
}

}  // namespace
}  // namespace cmbrl

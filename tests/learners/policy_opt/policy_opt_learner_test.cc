#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <string>
#include <vector>

namespace cmbrl {
namespace {

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
    context.cpu_seconds = [] { return 0.0; };
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

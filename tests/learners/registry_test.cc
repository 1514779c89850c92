#include "cmbrl/learners/registry.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cmbrl/planning/reward_term.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

// Every algorithm of run/algorithms.h has a learner, built from a tiny config, whose progress
// header is its family's: the smoke test that exercises every registry entry.
TEST(LearnerRegistryTest, EveryAlgorithmBuildsItsFamilysLearner) {
  int built = 0;
  for (const AlgorithmEntry& entry : Algorithms()) {
    SCOPED_TRACE(entry.name);
    TrainConfig config = ParseTrainConfig(
        entry.family == &MpcFamily()
            ? "task: PointGoal1\nalgorithm: mpc\ntraining: {pretrain_episodes: 2, "
              "pretrain_steps: 5, total_steps: 20}\nensemble: {hidden_sizes: [8]}\n"
              "classifier: {rounds: 2}\nplanning: {population: 12, elites: 4, "
              "min_feasible_elites: 2, max_iterations: 1, random_samples: 8, horizon: 2}\n"
            : "task: PointGoal1\nvariant: paper-lidar\nalgorithm: " + entry.name +
                  "\ntraining: {total_steps: 600}\npolicy_optimisation: {steps_per_epoch: 300, "
                  "envs: 1, env_threads: 1, policy_hidden: [8], value_hidden: [8]}\n",
        "registry test");
    const std::unique_ptr<Learner> learner = MakeLearner(config);
    ASSERT_NE(learner, nullptr);
    // The learner's own columns are its family sheet's, the one list reports read them by.
    EXPECT_EQ(learner->ProgressHeader(), entry.family->ProgressHeader());
    EXPECT_TRUE(RegistrationOf(*entry.family).load_agent) << "no way to load its trained agent";
    ++built;
  }
  EXPECT_EQ(built, 6);  // mpc, trpo, trpo-lagrangian, cpo, ppo, ppo-lagrangian
  TrainConfig unknown;
  unknown.algorithm = "sac";
  EXPECT_THAT(testing::ErrorMessage([&] { MakeLearner(unknown); }),
              ::testing::HasSubstr("unknown algorithm 'sac'"));
}

// objective.reward: python needs the reward term from the program (Python): without one the
// learner is refused by its key before anything is built; with one it plans with it.
TEST(LearnerRegistryTest, APythonRewardRunNeedsItsRewardTermGiven) {
  const TrainConfig config = ParseTrainConfig(
      "task: PointGoal1\ntraining: {pretrain_episodes: 2, pretrain_steps: 5, total_steps: 20}\n"
      "ensemble: {hidden_sizes: [8]}\nclassifier: {rounds: 2}\nplanning: {population: 12, "
      "elites: 4, min_feasible_elites: 2, max_iterations: 1, horizon: 2}\n"
      "objective: {reward: python}\n",
      "registry test");
  EXPECT_THAT(testing::ErrorMessage([&] { MakeLearner(config); }),
              ::testing::HasSubstr("objective.reward is 'python': the run plans with a reward "
                                   "function given from Python"));
  int made = 0;
  LearnerInputs inputs;
  inputs.python_reward = [&made]() -> std::unique_ptr<RewardTerm> {
    ++made;
    return MakeAnalyticReward(kGoalDistanceReward, TrajectoryObjectiveOptions{}, {});
  };
  EXPECT_NE(MakeLearner(config, inputs), nullptr);
  EXPECT_EQ(made, 1);
}

}  // namespace
}  // namespace cmbrl

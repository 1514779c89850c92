#include "cmbrl/env/vector_env.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cmbrl/env/registry.h"

namespace cmbrl {
namespace {

std::vector<std::unique_ptr<Env>> Envs(const std::string& task, int n) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int k = 0; k < n; ++k) envs.push_back(MakeEnv(task));
  return envs;
}

// Each row is what that environment alone does; an ended episode starts the next in the same
// step, its last observation kept aside.
TEST(VectorEnvTest, RowsAreTheEnvironmentsOwnStepsWithAutomaticResets) {
  const int n = 3;
  VectorEnv vector(Envs("PointGoal1", n), 2);
  std::vector<std::unique_ptr<Env>> alone = Envs("PointGoal1", n);
  const int width = alone[0]->observation_spec().size();
  const std::vector<double> first = vector.Reset(20);
  for (int k = 0; k < n; ++k) {
    const std::vector<double> expected = alone[k]->Reset(20 + k);
    EXPECT_EQ(std::vector<double>(first.begin() + k * width, first.begin() + (k + 1) * width),
              expected);
  }
  int resets = 0;
  for (int t = 0; t < alone[0]->max_episode_steps() + 3; ++t) {
    std::vector<double> actions;
    for (int k = 0; k < n; ++k)
      actions.insert(actions.end(), {0.5 - 0.3 * k, std::fmod(0.1 * t, 1.0)});
    const VectorStep step = vector.Step(actions);
    for (int k = 0; k < n; ++k) {
      StepResult expected = alone[k]->Step({actions[2 * k], actions[2 * k + 1]});
      EXPECT_EQ(step.rewards[k], expected.reward);
      EXPECT_EQ(step.costs[k], expected.cost);
      EXPECT_EQ(step.truncated[k] != 0, expected.truncated);
      const auto row = [&](const std::vector<double>& all) {
        return std::vector<double>(all.begin() + k * width, all.begin() + (k + 1) * width);
      };
      if (expected.terminated || expected.truncated) {
        EXPECT_EQ(row(step.final_observations), expected.observation);
        expected.observation = alone[k]->Reset();
        ++resets;
      }
      ASSERT_EQ(row(step.observations), expected.observation) << "step " << t << " env " << k;
    }
  }
  EXPECT_EQ(resets, n);
}

TEST(VectorEnvTest, BadActionsAreNamedBeforeAnyEnvironmentSteps) {
  VectorEnv vector(Envs("CarGoal1", 2), 2);
  vector.Reset(0);
  EXPECT_THROW(vector.Step({0.0, 0.0}), Error);
  try {
    vector.Step({0.0, 0.0, std::nan(""), 0.0});
    FAIL() << "a NaN action was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("environment 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(VectorEnv({}, 1), Error);
  EXPECT_THROW(VectorEnv(Envs("CarGoal1", 1), 1, std::chrono::microseconds(-1)), Error);
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/env/vector_env.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "cmbrl/env/registry.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

std::vector<std::unique_ptr<Env>> Envs(const std::string& task, int n) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int k = 0; k < n; ++k) envs.push_back(MakeEnv(task));
  return envs;
}

// Each row is what that environment alone does; an ended episode starts the next in the same
// step, its last observation kept aside.
// Environments for a vector are made only when they all fit the machine's memory: the first is
// measured, the count refused by name otherwise (100,000 of them had no bound).
TEST(VectorEnvTest, MakeEnvsRefusesACountThatDoesNotFitTheMemory) {
  EXPECT_EQ(MakeEnvs("PointGoal1", Variant::kPaper, Spawn::kStanding, 3).size(), 3u);
  EXPECT_THAT(testing::ErrorMessage(
                  [] { MakeEnvs("PointGoal1", Variant::kPaper, Spawn::kStanding, 0); }),
              ::testing::HasSubstr("num_envs is 0: expected at least 1"));
  const std::string message = testing::ErrorMessage(
      [] { MakeEnvs("CarGoal2", Variant::kPaper, Spawn::kStanding, 100'000'000); });
  EXPECT_THAT(message, ::testing::HasSubstr("num_envs 100000000: 100000000 environments of "
                                            "CarGoal2 ("));
  EXPECT_THAT(message, ::testing::HasSubstr("MiB each) would need about"));
  EXPECT_THAT(message, ::testing::HasSubstr("use fewer environments"));
}

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

// Autoreset disabled (Gymnasium 1.x's DISABLED): an ended environment keeps its last
// observation and refuses to step until ResetWhere resets it, with or without a seed; an
// inactive environment does not step at all.
TEST(VectorEnvTest, DisabledAutoresetWaitsForAMaskedResetAndInactiveEnvironmentsStayPut) {
  const int n = 2;
  VectorEnv vector(Envs("PointGoal1", n), 2, VectorEnv::kDefaultSpin, Autoreset::kDisabled);
  std::vector<std::unique_ptr<Env>> alone = Envs("PointGoal1", n);
  const int width = alone[0]->observation_spec().size();
  const auto row = [&](const std::vector<double>& all, int k) {
    return std::vector<double>(all.begin() + k * width, all.begin() + (k + 1) * width);
  };
  EXPECT_THROW(vector.Step({0.1, 0.1, 0.1, 0.1}), Error);  // never reset
  const std::vector<double> first = vector.ResetWhere({1, 1}, {7, 90});
  EXPECT_EQ(row(first, 0), alone[0]->Reset(7));
  EXPECT_EQ(row(first, 1), alone[1]->Reset(90));
  // Environment 1 sits out three steps; then both step until environment 0's episode ends.
  for (int t = 0; t < 3; ++t) {
    const VectorStep step = vector.Step({0.3, -0.2, 99.0, std::nan("")}, {1, 0});
    const StepResult expected = alone[0]->Step({0.3, -0.2});
    EXPECT_EQ(row(step.observations, 0), expected.observation);
    EXPECT_EQ(row(step.observations, 1), std::vector<double>(width, 0.0));
    EXPECT_EQ(step.rewards[1], 0.0);
  }
  bool ended = false;
  for (int t = 0; t < alone[0]->max_episode_steps() && !ended; ++t) {
    const VectorStep step = vector.Step({0.5, 0.1, 0.5, 0.1});
    const StepResult expected0 = alone[0]->Step({0.5, 0.1});
    const StepResult expected1 = alone[1]->Step({0.5, 0.1});
    EXPECT_EQ(row(step.observations, 0), expected0.observation);  // the last one, not reset
    EXPECT_EQ(row(step.observations, 1), expected1.observation);
    ended = step.truncated[0] != 0 || step.terminated[0] != 0;
    EXPECT_EQ(ended, expected0.truncated || expected0.terminated);
  }
  ASSERT_TRUE(ended);
  try {
    vector.Step({0.0, 0.0, 0.0, 0.0});
    FAIL() << "an ended environment stepped without a reset";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("environment 0 is stepped before a reset"),
              std::string::npos)
        << e.what();
  }
  vector.Step({0.0, 0.0, 0.2, 0.2}, {0, 1});  // the other may go on alone
  alone[1]->Step({0.2, 0.2});
  const std::vector<double> next = vector.ResetWhere({1, 0});  // continues the generator
  EXPECT_EQ(row(next, 0), alone[0]->Reset());
  EXPECT_EQ(row(next, 1), std::vector<double>(width, 0.0));
  const VectorStep step = vector.Step({0.1, 0.1, 0.1, 0.1});
  EXPECT_EQ(row(step.observations, 0), alone[0]->Step({0.1, 0.1}).observation);
  EXPECT_EQ(row(step.observations, 1), alone[1]->Step({0.1, 0.1}).observation);
  EXPECT_THROW(vector.ResetWhere({1}), Error);
  EXPECT_THROW(vector.ResetWhere({1, 1}, {3}), Error);
  EXPECT_THROW(vector.Step({0.1, 0.1, 0.1, 0.1}, {1}), Error);
}

// A vector's state, restored into another made the same way, steps and resets as the first
// does from there, an ended environment still waiting for its reset; a state that does not fit
// is refused with the vector unchanged.
TEST(VectorEnvTest, AStateRestoredStepsAndResetsAsTheOriginalDoes) {
  VectorEnv a(Envs("PointGoal1", 2), 2, VectorEnv::kDefaultSpin, Autoreset::kDisabled);
  VectorEnv b(Envs("PointGoal1", 2), 2, VectorEnv::kDefaultSpin, Autoreset::kDisabled);
  a.ResetWhere({1, 1}, {5, 6});
  for (int t = 0; t < 10; ++t) a.Step({0.9, 0.4, 0.0, 0.0}, {1, 0});  // 0 ends 10 steps early
  bool ended = false;
  for (int t = 0; t < 2000 && !ended; ++t) {
    const VectorStep step = a.Step({0.9, 0.4, 0.2, -0.3}, {1, 1});
    ended = step.truncated[0] != 0 || step.terminated[0] != 0;
  }
  ASSERT_TRUE(ended);  // environment 0 waits for a reset, 1 may go on
  const VectorEnvState state = a.State();
  EXPECT_EQ(state.needs_reset, (std::vector<std::uint8_t>{1, 0}));
  b.SetState(state);
  EXPECT_THROW(b.Step({0.0, 0.0, 0.1, 0.1}), Error);
  EXPECT_EQ(b.ResetWhere({1, 0}), a.ResetWhere({1, 0}));  // the generators continue alike
  for (int t = 0; t < 5; ++t) {
    const VectorStep x = a.Step({0.1, 0.2, 0.3, 0.4}, {1, 1});
    const VectorStep y = b.Step({0.1, 0.2, 0.3, 0.4}, {1, 1});
    EXPECT_EQ(x.observations, y.observations);
    EXPECT_EQ(x.rewards, y.rewards);
    EXPECT_EQ(x.costs, y.costs);
  }
  VectorEnvState wrong = a.State();
  const VectorEnvState before = wrong;
  wrong.needs_reset.pop_back();
  EXPECT_THAT(testing::ErrorMessage([&] { b.SetState(wrong); }),
              ::testing::HasSubstr("1 reset flags for 2 environments"));
  wrong = before;
  wrong.envs[1] = "not a state";
  b.SetState(a.State());
  const VectorEnvState kept = b.State();
  a.Step({0.1, 0.2, 0.3, 0.4}, {1, 1});
  EXPECT_THROW(b.SetState(wrong), Error);  // environment 0 was set before 1 refused
  EXPECT_EQ(b.State().envs, kept.envs);
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

namespace cmbrl {
namespace {

// Next-step autoreset (Gymnasium's default): the step after an episode ended resets that
// environment instead, its action unread (a NaN passes), with reward and cost 0 and `reset` set;
// adaptive threads give the same results as fixed ones.
TEST(VectorEnvTest, NextStepAutoresetResetsOnTheFollowingStep) {
  for (const bool adaptive : {false, true}) {
    SCOPED_TRACE(adaptive);
    VectorEnv vector(Envs("PointGoal1", 2), 2, VectorEnv::kDefaultSpin, Autoreset::kNextStep);
    vector.SetAdaptiveThreads(adaptive);
    EXPECT_EQ(vector.adaptive_threads(), adaptive);
    std::vector<std::unique_ptr<Env>> alone = Envs("PointGoal1", 1);
    const int width = alone[0]->observation_spec().size();
    vector.Reset(3);
    alone[0]->Reset(3);
    VectorStep step;
    bool ended = false;  // a goal met inside an action repeat lengthens an episode
    for (int t = 0; t < 10 * alone[0]->max_episode_steps() && !ended; ++t) {
      step = vector.Step({0.4, 0.2, 0.4, 0.2});
      const StepResult expected = alone[0]->Step({0.4, 0.2});
      ASSERT_EQ(std::vector<double>(step.observations.begin(), step.observations.begin() + width),
                expected.observation);
      EXPECT_EQ(step.reset[0], 0);
      ended = expected.terminated || expected.truncated;
      EXPECT_EQ(step.terminated[0] || step.truncated[0], ended);
    }
    ASSERT_TRUE(ended);
    step = vector.Step({std::nan(""), 0.0, 0.4, 0.2});
    EXPECT_EQ(step.reset[0], 1);
    EXPECT_EQ(step.rewards[0], 0.0);
    EXPECT_EQ(step.truncated[0] + step.terminated[0], 0);
    EXPECT_EQ(std::vector<double>(step.observations.begin(), step.observations.begin() + width),
              alone[0]->Reset());
    step = vector.Step({0.4, 0.2, 0.4, 0.2});
    EXPECT_EQ(step.reset[0], 0);
    EXPECT_EQ(std::vector<double>(step.observations.begin(), step.observations.begin() + width),
              alone[0]->Step({0.4, 0.2}).observation);
  }
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/planning/trajectory_objective.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/error_message.h"
#include "tests/planning/fake_models.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;
using testing::HalfPlaneCost;
using testing::LinearDynamics;
using testing::StateWithGoal;

// One sequence of H identical actions: (1, H, 2).
torch::Tensor Repeat(float x, float y, int horizon) {
  return torch::tensor({x, y}).view({1, 1, 2}).expand({1, horizon, 2}).contiguous();
}

constexpr float kTol = 1e-5f;  // float32 arithmetic on values of order 1

TEST(TrajectoryObjectiveTest, PerMemberRolloutsAverageRewardAndTakeTheWorstConstraint) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {});
  objective.SetState(StateWithGoal(1.2f));
  // Two steps of (1, 0). Member 0 (gain 1): goal x 0.9, 0.6; robot x 0.3, 0.6 (unsafe at t 1).
  // Member 1 (gain 1.5): goal x 0.75, 0.3; robot x 0.45, 0.9 (unsafe at t 1).
  const ObjectiveValues v = objective.Evaluate(Repeat(1, 0, 2));
  EXPECT_NEAR(v.reward_cost.item<float>(), ((0.9 + 0.98 * 0.6) + (0.75 + 0.98 * 0.3)) / 2, kTol);
  EXPECT_NEAR(v.constraint_cost.item<float>(), 0.4, kTol);  // beta^1, the worse member
  EXPECT_EQ(objective.last_trajectories().sizes(), torch::IntArrayRef({2, 1, 2, 8}));
}

TEST(TrajectoryObjectiveTest, TheWorstMemberMakesASampleInfeasibleWhereTheMeanDoesNot) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective robust(dynamics, cost, Propagation::kPerMember, {});
  TrajectoryObjective mean(dynamics, cost, Propagation::kEnsembleMean, {});
  robust.SetState(StateWithGoal(1.2f));
  mean.SetState(StateWithGoal(1.2f));
  // Two steps of (0.6, 0): member 0 reaches x 0.36 (safe), member 1 x 0.54 (unsafe); their mean
  // 0.45 is safe.
  EXPECT_NEAR(robust.Evaluate(Repeat(0.6f, 0, 2)).constraint_cost.item<float>(), 0.4, kTol);
  EXPECT_EQ(mean.Evaluate(Repeat(0.6f, 0, 2)).constraint_cost.item<float>(), 0.0f);
}

TEST(TrajectoryObjectiveTest, MeanPropagationDiscountsTheConstraintWithGamma) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kEnsembleMean, {});
  objective.SetState(StateWithGoal(1.2f));
  // Mean gain 1.25: robot x 0.375, 0.75 (unsafe at t 1); goal x 0.825, 0.45.
  const ObjectiveValues v = objective.Evaluate(Repeat(1, 0, 2));
  EXPECT_NEAR(v.reward_cost.item<float>(), 0.825 + 0.98 * 0.45, kTol);
  EXPECT_NEAR(v.constraint_cost.item<float>(), 0.98, kTol);
  // Every member carries the mean trajectory.
  const torch::Tensor trajectories = objective.last_trajectories();
  EXPECT_TRUE(torch::equal(trajectories[0], trajectories[1]));
}

TEST(TrajectoryObjectiveTest, GoalBonusesApplyNearTheGoal) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {});
  objective.SetState(StateWithGoal(0.3f));
  // One step of (1, 0): member 0 lands on the goal (d 0), member 1 overshoots to d 0.15. As the
  // original's code ran, the at-goal test sees 0.15 - 5 < 0.1: both get -13.
  const ObjectiveValues v = objective.Evaluate(Repeat(1, 0, 1));
  EXPECT_NEAR(v.reward_cost.item<float>(), ((0.0 - 13.0) + (0.15 - 13.0)) / 2, kTol);
  // The written rule: -13 only below 0.1, -5 between 0.1 and 0.2.
  TrajectoryObjectiveOptions written;
  written.at_goal_test_after_near_bonus = false;
  TrajectoryObjective as_written(dynamics, cost, Propagation::kPerMember, written);
  as_written.SetState(StateWithGoal(0.3f));
  EXPECT_NEAR(as_written.Evaluate(Repeat(1, 0, 1)).reward_cost.item<float>(),
              ((0.0 - 13.0) + (0.15 - 5.0)) / 2, kTol);
}

TEST(TrajectoryObjectiveTest, ScoresManySamplesAtOnce) {
  LinearDynamics dynamics(3);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {});
  objective.SetState(StateWithGoal(2.0f));
  const torch::Tensor actions = torch::rand({50, 4, 2}) * 2 - 1;
  const ObjectiveValues all = objective.Evaluate(actions);
  ASSERT_EQ(all.reward_cost.sizes(), torch::IntArrayRef({50}));
  for (int i : {0, 17, 49}) {
    const ObjectiveValues one = objective.Evaluate(actions.narrow(0, i, 1));
    EXPECT_NEAR(all.reward_cost[i].item<float>(), one.reward_cost.item<float>(), kTol);
    EXPECT_EQ(all.constraint_cost[i].item<float>(), one.constraint_cost.item<float>());
  }
}

TEST(TrajectoryObjectiveTest, BadSettingsAndInputsAreNamed) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjectiveOptions options;
  options.goal_index = 7;
  EXPECT_EQ(
      ErrorMessage([&] { TrajectoryObjective(dynamics, cost, Propagation::kPerMember, options); }),
      "goal_index is 7: expected 0 to 6 for a state of 8 dimensions");
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {});
  EXPECT_THAT(ErrorMessage([&] { objective.Evaluate(Repeat(1, 0, 2)); }),
              ::testing::HasSubstr("before SetState"));
  EXPECT_THAT(ErrorMessage([&] { objective.SetState(torch::zeros({5})); }),
              ::testing::HasSubstr("planning state has shape [5]: expected (8)"));
}

}  // namespace
}  // namespace cmbrl

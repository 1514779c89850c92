#include "cmbrl/planning/trajectory_objective.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/xgboost_cost_model.h"
#include "tests/error_message.h"
#include "tests/planning/fake_models.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;
using testing::GoalTerm;
using testing::HalfPlaneCost;
using testing::LinearDynamics;
using testing::StateWithGoal;

// One sequence of H identical actions: (1, H, 2).
torch::Tensor Repeat(float x, float y, int horizon) {
  return torch::tensor({x, y}).view({1, 1, 2}).expand({1, horizon, 2}).contiguous();
}

constexpr float kObjectiveTol = 1e-5f;  // float32 arithmetic on values of order 1

// A reward term that reads every argument and records them: the cost of a step is its action's
// first component.
class RecordingTerm final : public RewardTerm {
 public:
  explicit RecordingTerm(std::vector<torch::Tensor>* seen) : seen_(seen) {}
  torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                     const torch::Tensor& next_states) const override {
    *seen_ = {states, actions, next_states};
    return actions.select(-1, 0);
  }
  bool reads_states_and_actions() const override { return true; }

 private:
  std::vector<torch::Tensor>* seen_;
};

// Costs every step 1 (a reward term), and ends the episode at step `end` (a termination term).
class UnitCost final : public RewardTerm {
 public:
  torch::Tensor Cost(const torch::Tensor&, const torch::Tensor&,
                     const torch::Tensor& next_states) const override {
    return torch::ones_like(next_states.select(-1, 0));
  }
  bool reads_states_and_actions() const override { return false; }
};
class EndsAtStep final : public TerminationTerm {
 public:
  explicit EndsAtStep(int end) : end_(end) {}
  torch::Tensor Terminal(const torch::Tensor& states, const torch::Tensor& actions,
                         const torch::Tensor& next_states) const override {
    EXPECT_TRUE(states.defined() && actions.defined());  // it reads them, as a term may
    torch::Tensor terminal = torch::zeros_like(next_states.select(-1, 0));
    terminal[end_].fill_(1.0f);
    return terminal;
  }

 private:
  int end_;
};

// A terminal step counts, the steps after it do not, in both sums: a unit cost over 3 steps
// ending at step 1 sums to 1 + 0.98, not 1 + 0.98 + 0.98^2.
TEST(TrajectoryObjectiveTest, ATerminalStepCutsTheDiscountedSums) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  const torch::Tensor actions = torch::full({2, 3, 2}, 0.5f);
  for (const Propagation propagation : {Propagation::kPerMember, Propagation::kEnsembleMean}) {
    TrajectoryObjective open(dynamics, cost, propagation, {}, std::make_unique<UnitCost>());
    TrajectoryObjective ended(dynamics, cost, propagation, {}, std::make_unique<UnitCost>(),
                              std::make_unique<EndsAtStep>(1));
    open.SetState(StateWithGoal(1.0f));
    ended.SetState(StateWithGoal(1.0f));
    const ObjectiveValues all = open.Evaluate(actions);
    const ObjectiveValues cut = ended.Evaluate(actions);
    EXPECT_NEAR(all.reward_cost[0].item<float>(), 1 + 0.98 + 0.98 * 0.98, kObjectiveTol);
    EXPECT_NEAR(cut.reward_cost[0].item<float>(), 1 + 0.98, kObjectiveTol);
    // The constraint's sum is cut alike: no violation after the end counts.
    EXPECT_LE(cut.constraint_cost[0].item<float>(), all.constraint_cost[0].item<float>());
  }
}

// A term that reads states and actions gets, for every step t, the state it starts from (the
// planning state at t = 0, the prediction of step t - 1 after), its action and its prediction,
// laid out (H, E', N, ...) as the trajectories are; its costs are summed like the goal's.
TEST(TrajectoryObjectiveTest, ATermThatReadsStatesAndActionsGetsEachStepsStartActionAndEnd) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  for (const Propagation propagation : {Propagation::kPerMember, Propagation::kEnsembleMean}) {
    std::vector<torch::Tensor> seen;
    TrajectoryObjective objective(dynamics, cost, propagation, {},
                                  std::make_unique<RecordingTerm>(&seen));
    const torch::Tensor start = StateWithGoal(1.0f);
    objective.SetState(start);
    const int horizon = 3, samples = 4;
    const torch::Tensor actions =
        torch::linspace(-0.9, 0.9, samples * horizon * 2).view({samples, horizon, 2});
    const ObjectiveValues values = objective.Evaluate(actions);
    ASSERT_EQ(seen.size(), 3u);
    const torch::Tensor& states = seen[0];
    const torch::Tensor& step_actions = seen[1];
    const torch::Tensor& next_states = seen[2];
    const std::int64_t rows = propagation == Propagation::kPerMember ? 2 : 1;
    EXPECT_EQ(states.sizes(), next_states.sizes());
    EXPECT_EQ(states.sizes(), (torch::IntArrayRef{horizon, rows, samples, start.size(0)}));
    EXPECT_TRUE(torch::equal(states[0][0][0], start));
    EXPECT_TRUE(
        torch::equal(states.narrow(0, 1, horizon - 1), next_states.narrow(0, 0, horizon - 1)));
    for (int t = 0; t < horizon; ++t) {
      EXPECT_TRUE(torch::equal(step_actions[t][0], actions.select(1, t))) << t;
    }
    // The reward cost is the discounted sum of the first action components (gamma 0.98).
    const torch::Tensor expected =
        actions.select(2, 0).select(1, 0) + 0.98f * actions.select(2, 0).select(1, 1) +
        static_cast<float>(0.98 * 0.98) * actions.select(2, 0).select(1, 2);
    EXPECT_TRUE(torch::allclose(values.reward_cost, expected, kObjectiveTol, kObjectiveTol));
  }
}

TEST(TrajectoryObjectiveTest, PerMemberRolloutsAverageRewardAndTakeTheWorstConstraint) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {}, GoalTerm());
  objective.SetState(StateWithGoal(1.2f));
  // Two steps of (1, 0). Member 0 (gain 1): goal x 0.9, 0.6; robot x 0.3, 0.6 (unsafe at t 1).
  // Member 1 (gain 1.5): goal x 0.75, 0.3; robot x 0.45, 0.9 (unsafe at t 1).
  const ObjectiveValues v = objective.Evaluate(Repeat(1, 0, 2));
  EXPECT_NEAR(v.reward_cost.item<float>(), ((0.9 + 0.98 * 0.6) + (0.75 + 0.98 * 0.3)) / 2,
              kObjectiveTol);
  EXPECT_NEAR(v.constraint_cost.item<float>(), 0.4, kObjectiveTol);  // beta^1, the worse member
  EXPECT_EQ(objective.last_trajectories().sizes(), torch::IntArrayRef({2, 1, 2, 8}));
}

TEST(TrajectoryObjectiveTest, TheWorstMemberMakesASampleInfeasibleWhereTheMeanDoesNot) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective robust(dynamics, cost, Propagation::kPerMember, {}, GoalTerm());
  TrajectoryObjective mean(dynamics, cost, Propagation::kEnsembleMean, {}, GoalTerm());
  robust.SetState(StateWithGoal(1.2f));
  mean.SetState(StateWithGoal(1.2f));
  // Two steps of (0.6, 0): member 0 reaches x 0.36 (safe), member 1 x 0.54 (unsafe); their mean
  // 0.45 is safe.
  EXPECT_NEAR(robust.Evaluate(Repeat(0.6f, 0, 2)).constraint_cost.item<float>(), 0.4,
              kObjectiveTol);
  EXPECT_EQ(mean.Evaluate(Repeat(0.6f, 0, 2)).constraint_cost.item<float>(), 0.0f);
}

TEST(TrajectoryObjectiveTest, MeanPropagationDiscountsTheConstraintWithGamma) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kEnsembleMean, {}, GoalTerm());
  objective.SetState(StateWithGoal(1.2f));
  // Mean gain 1.25: robot x 0.375, 0.75 (unsafe at t 1); goal x 0.825, 0.45.
  const ObjectiveValues v = objective.Evaluate(Repeat(1, 0, 2));
  EXPECT_NEAR(v.reward_cost.item<float>(), 0.825 + 0.98 * 0.45, kObjectiveTol);
  EXPECT_NEAR(v.constraint_cost.item<float>(), 0.98, kObjectiveTol);
  // Every member carries the mean trajectory.
  const torch::Tensor trajectories = objective.last_trajectories();
  EXPECT_TRUE(torch::equal(trajectories[0], trajectories[1]));
}

TEST(TrajectoryObjectiveTest, GoalBonusesApplyNearTheGoal) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {}, GoalTerm());
  objective.SetState(StateWithGoal(0.3f));
  // One step of (1, 0): member 0 lands on the goal (d 0), member 1 overshoots to d 0.15. As the
  // original's code ran, the at-goal test sees 0.15 - 5 < 0.1: both get -13.
  const ObjectiveValues v = objective.Evaluate(Repeat(1, 0, 1));
  EXPECT_NEAR(v.reward_cost.item<float>(), ((0.0 - 13.0) + (0.15 - 13.0)) / 2, kObjectiveTol);
  // The written rule: -13 only below 0.1, -5 between 0.1 and 0.2.
  TrajectoryObjectiveOptions written;
  written.at_goal_test_after_near_bonus = false;
  TrajectoryObjective as_written(dynamics, cost, Propagation::kPerMember, written,
                                 GoalTerm(written));
  as_written.SetState(StateWithGoal(0.3f));
  EXPECT_NEAR(as_written.Evaluate(Repeat(1, 0, 1)).reward_cost.item<float>(),
              ((0.0 - 13.0) + (0.15 - 5.0)) / 2, kObjectiveTol);
}

TEST(TrajectoryObjectiveTest, ScoresManySamplesAtOnce) {
  LinearDynamics dynamics(3);
  HalfPlaneCost cost;
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {}, GoalTerm());
  objective.SetState(StateWithGoal(2.0f));
  const torch::Tensor actions = torch::rand({50, 4, 2}) * 2 - 1;
  const ObjectiveValues all = objective.Evaluate(actions);
  ASSERT_EQ(all.reward_cost.sizes(), torch::IntArrayRef({50}));
  for (int i : {0, 17, 49}) {
    const ObjectiveValues one = objective.Evaluate(actions.narrow(0, i, 1));
    EXPECT_NEAR(all.reward_cost[i].item<float>(), one.reward_cost.item<float>(), kObjectiveTol);
    EXPECT_EQ(all.constraint_cost[i].item<float>(), one.constraint_cost.item<float>());
  }
}

// The scores as the objective defined them before it scored all steps at once (v0.9): step by
// step, the goal distance and the bonuses, then sum += discount * cost with a double discount.
ObjectiveValues StepByStepScores(const torch::Tensor& trajectories, const CostModel& cost,
                                 bool per_member, const TrajectoryObjectiveOptions& o) {
  const std::int64_t members = per_member ? trajectories.size(0) : 1;
  torch::Tensor reward = torch::zeros({members, trajectories.size(1)});
  torch::Tensor constraint = torch::zeros_like(reward);
  double reward_discount = 1.0, constraint_discount = 1.0;
  for (std::int64_t t = 0; t < trajectories.size(2); ++t) {
    const torch::Tensor states = trajectories.select(2, t).narrow(0, 0, members);  // (E', N, S)
    const torch::Tensor distance = states.narrow(-1, o.goal_index, 2).norm(2, -1);
    const torch::Tensor near = distance - o.near_goal_bonus * (distance < o.near_goal_radius);
    const torch::Tensor tested = o.at_goal_test_after_near_bonus ? near : distance;
    reward = reward + reward_discount * (near - o.at_goal_bonus * (tested < o.at_goal_radius));
    constraint = constraint + constraint_discount * cost.PredictViolation(states.contiguous());
    reward_discount *= o.gamma;
    constraint_discount *= per_member ? o.beta : o.gamma;
  }
  return per_member ? ObjectiveValues{reward.mean(0), std::get<0>(constraint.max(0))}
                    : ObjectiveValues{reward[0], constraint[0]};
}

TEST(TrajectoryObjectiveTest, AllStepsAtOnceGiveTheStepByStepScoresBitForBit) {
  // Learned models: a random ensemble and a classifier of the half-space state[0] > -0.1.
  constexpr int kStateDim = 12, kActionDim = 2;
  EnsembleOptions ensemble_options;
  ensemble_options.hidden_sizes = {32, 32};
  ensemble_options.predict_delta = true;
  EnsembleDynamics dynamics(kStateDim, kActionDim, ensemble_options, 7);
  torch::manual_seed(7);
  const torch::Tensor rows = torch::randn({600, kStateDim}) * 0.2;
  const torch::Tensor unsafe_rows = rows.select(1, 0) > -0.1;
  const torch::Tensor safe = rows.index({~unsafe_rows}).contiguous();
  const torch::Tensor unsafe = rows.index({unsafe_rows}).contiguous();
  XgbCostModel cost(kStateDim, XgbCostModelOptions{}, 7);
  cost.FitArrays(safe.data_ptr<float>(), static_cast<int>(safe.size(0)), unsafe.data_ptr<float>(),
                 static_cast<int>(unsafe.size(0)));
  const torch::Tensor state = torch::randn({kStateDim}) * 0.1;
  const torch::Tensor actions = torch::rand({300, 10, kActionDim}) * 2 - 1;
  for (const Propagation propagation : {Propagation::kPerMember, Propagation::kEnsembleMean}) {
    for (const bool after_near_bonus : {true, false}) {
      TrajectoryObjectiveOptions options;
      options.goal_index = 4;
      // Radii that some predicted states fall within, so that every branch of the cost is taken.
      options.near_goal_radius = 1.0;
      options.at_goal_radius = 0.6;
      options.at_goal_test_after_near_bonus = after_near_bonus;
      TrajectoryObjective objective(dynamics, cost, propagation, options, GoalTerm(options));
      objective.SetState(state);
      const ObjectiveValues all = objective.Evaluate(actions);
      const ObjectiveValues expected = StepByStepScores(
          objective.last_trajectories(), cost, propagation == Propagation::kPerMember, options);
      EXPECT_TRUE(torch::equal(all.reward_cost, expected.reward_cost));
      EXPECT_TRUE(torch::equal(all.constraint_cost, expected.constraint_cost));
      // Not a vacuous comparison: some predicted states violate, some do not; some earn both
      // bonuses, some neither.
      const torch::Tensor trajectories = objective.last_trajectories();
      const torch::Tensor violating = cost.PredictViolation(trajectories) > 0;
      EXPECT_TRUE(violating.any().item<bool>() && (~violating).any().item<bool>());
      const torch::Tensor distance = trajectories.narrow(-1, options.goal_index, 2).norm(2, -1);
      EXPECT_TRUE((distance < options.at_goal_radius).any().item<bool>());
      EXPECT_TRUE((distance > options.near_goal_radius).any().item<bool>());
    }
  }
}

TEST(TrajectoryObjectiveTest, BadSettingsAndInputsAreNamed) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  TrajectoryObjectiveOptions options;
  options.goal_index = 7;
  EXPECT_EQ(ErrorMessage([&] {
              TrajectoryObjective(dynamics, cost, Propagation::kPerMember, options,
                                  GoalTerm(options));
            }),
            "goal_index is 7: expected 0 to 6 for a state of 8 dimensions");
  TrajectoryObjective objective(dynamics, cost, Propagation::kPerMember, {}, GoalTerm());
  EXPECT_THAT(ErrorMessage([&] { objective.Evaluate(Repeat(1, 0, 2)); }),
              ::testing::HasSubstr("before SetState"));
  EXPECT_THAT(ErrorMessage([&] { objective.SetState(torch::zeros({5})); }),
              ::testing::HasSubstr("planning state has shape [5]: expected (8)"));
}

}  // namespace
}  // namespace cmbrl

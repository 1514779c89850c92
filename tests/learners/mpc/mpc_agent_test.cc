#include "cmbrl/learners/mpc/mpc_agent.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "tests/error_message.h"
#include "tests/planning/fake_models.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;
using testing::GoalTerm;
using testing::HalfPlaneCost;
using testing::LinearDynamics;

std::vector<double> Observation(double goal_x, double goal_y) {
  std::vector<double> observation(8, 0.0);
  observation[6] = goal_x;
  observation[7] = goal_y;
  return observation;
}

TEST(MpcAgentTest, EveryPlannerHeadsForAGoalInTheSafeHalf) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  for (const std::string& planner : PlannerNames()) {
    MpcAgent agent(dynamics, cost, planner, PlannerSettings{}, {}, GoalTerm(), 1);
    agent.BeginEpisode();
    // Goal 1.5 m to the left (+y), nowhere near the unsafe half-plane x > 0.5.
    const std::vector<double> action = agent.Act(Observation(0.0, 1.5));
    ASSERT_EQ(action.size(), 2u);
    EXPECT_GT(action[1], 0.5) << planner;
    EXPECT_LE(std::abs(action[0]), 1.0) << planner;
    EXPECT_GE(agent.last_plan().iterations, 1);
    // A few wild samples still cross x > 0.5; most do not.
    EXPECT_GT(agent.last_plan().feasible_fraction, 0.5) << planner;
    EXPECT_GT(agent.last_plan().milliseconds, 0.0);
  }
}

TEST(MpcAgentTest, RceKeepsEveryMembersPredictionOutOfTheUnsafeHalf) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  MpcAgent agent(dynamics, cost, "rce", PlannerSettings{}, {}, GoalTerm(), 2);
  // Goal straight ahead beyond the boundary x = 0.5: the robot may approach but no member's
  // trajectory of the final plan may cross.
  agent.Act(Observation(2.0, 0.0));
  const torch::Tensor plan = agent.last_result().sequence.unsqueeze(0);
  agent.objective().SetState(
      torch::tensor(Observation(2.0, 0.0), torch::kDouble).to(torch::kFloat));
  EXPECT_EQ(agent.objective().Evaluate(plan).constraint_cost.item<float>(), 0.0f);
  EXPECT_GT(agent.last_result().action[0].item<float>(), 0.0f);  // still moving toward it
}

// A model that predicts NaN: the agent must not pass it on as an action.
class NanDynamics final : public DynamicsModel {
 public:
  int state_dim() const override { return 8; }
  int action_dim() const override { return 2; }
  int ensemble_size() const override { return 2; }
  torch::Tensor Predict(const torch::Tensor& s, const torch::Tensor& a) const override {
    return PredictUnchecked(s, a);
  }
  torch::Tensor PredictUnchecked(const torch::Tensor& states, const torch::Tensor&) const override {
    return torch::full_like(states, std::numeric_limits<float>::quiet_NaN());
  }
};

TEST(MpcAgentTest, NanPredictionsAreReportedNotExecuted) {
  NanDynamics dynamics;
  HalfPlaneCost cost;
  // The elite mean of finite samples would still be a finite action: the scores are checked.
  for (const std::string& planner : PlannerNames()) {
    MpcAgent agent(dynamics, cost, planner, PlannerSettings{}, {}, GoalTerm(), 3);
    EXPECT_THAT(ErrorMessage([&] { agent.Act(Observation(1.0, 0.0)); }),
                ::testing::HasSubstr("predicted NaN or infinity while planning"))
        << planner;
  }
}

TEST(MpcAgentTest, BadObservationsAreNamed) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  MpcAgent agent(dynamics, cost, "random", PlannerSettings{}, {}, GoalTerm(), 4);
  EXPECT_EQ(ErrorMessage([&] { agent.Act(std::vector<double>(5, 0.0)); }),
            "observation has 5 entries, the dynamics model expects 8");
  std::vector<double> bad = Observation(1.0, 0.0);
  bad[3] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ErrorMessage([&] { agent.Act(bad); }),
            "observation entry 3 is inf: expected a finite number");
}

TEST(MpcAgentTest, SameSeedSameActions) {
  LinearDynamics dynamics(2);
  HalfPlaneCost cost;
  MpcAgent a(dynamics, cost, "rce", PlannerSettings{}, {}, GoalTerm(), 5);
  MpcAgent b(dynamics, cost, "rce", PlannerSettings{}, {}, GoalTerm(), 5);
  for (int step = 0; step < 3; ++step) {
    EXPECT_EQ(a.Act(Observation(1.0, 0.5)), b.Act(Observation(1.0, 0.5)));
  }
}

}  // namespace
}  // namespace cmbrl

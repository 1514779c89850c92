// Hand-computable models for objective and agent tests.
#pragma once

#include <torch/torch.h>

#include "cmbrl/models/cost_model.h"
#include "cmbrl/models/dynamics_model.h"
#include "cmbrl/planning/reward_term.h"

namespace cmbrl::testing {

// State (8): robot x, y, four unused, goal ego x, y. Member e moves the robot by
// (1 + 0.5 e) * 0.3 * action and the goal by the opposite.
class LinearDynamics final : public DynamicsModel {
 public:
  explicit LinearDynamics(int members) : members_(members) {}
  int state_dim() const override { return 8; }
  int action_dim() const override { return 2; }
  int ensemble_size() const override { return members_; }
  torch::Tensor Predict(const torch::Tensor& s, const torch::Tensor& a) const override {
    return PredictUnchecked(s, a);
  }
  torch::Tensor PredictUnchecked(const torch::Tensor& states,
                                 const torch::Tensor& actions) const override {
    const torch::Tensor gain =
        (1 + 0.5 * torch::arange(members_, states.options())).view({members_, 1, 1});
    const torch::Tensor step = 0.3 * gain * actions;  // (E, N, 2)
    torch::Tensor next = states.clone();
    next.narrow(2, 0, 2) += step;
    next.narrow(2, 6, 2) -= step;
    return next;
  }

 private:
  int members_;
};

// Unsafe where robot x > 0.5.
class HalfPlaneCost final : public CostModel {
 public:
  int state_dim() const override { return 8; }
  torch::Tensor PredictViolation(const torch::Tensor& states) const override {
    return (states.select(-1, 0) > 0.5).to(torch::kFloat);
  }
  std::vector<std::uint8_t> PredictRows(const float* states, int rows) const override {
    std::vector<std::uint8_t> out(rows);
    for (int i = 0; i < rows; ++i) out[i] = states[8 * i] > 0.5f;
    return out;
  }
};

// The robot at the origin with the goal at ego (goal_x, 0).
// The Goal tasks' analytic reward term with the objective's options.
inline std::unique_ptr<RewardTerm> GoalTerm(const TrajectoryObjectiveOptions& options = {}) {
  return MakeAnalyticReward(kGoalDistanceReward, options, {});
}

inline torch::Tensor StateWithGoal(float goal_x) {
  torch::Tensor state = torch::zeros({8});
  state[6] = goal_x;
  return state;
}

}  // namespace cmbrl::testing

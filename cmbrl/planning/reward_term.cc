#include "cmbrl/planning/reward_term.h"

#include <fmt/ranges.h>
#include <torch/torch.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

GoalDistanceTerm::GoalDistanceTerm(TrajectoryObjectiveOptions options)
    : options_(std::move(options)) {}

torch::Tensor GoalDistanceTerm::Cost(const torch::Tensor&, const torch::Tensor&,
                                     const torch::Tensor& next_states) const {
  const torch::Tensor goal = next_states.narrow(-1, options_.goal_index, 2);
  const torch::Tensor distance = goal.norm(2, -1);
  const torch::Tensor near =
      distance - options_.near_goal_bonus * (distance < options_.near_goal_radius);
  const torch::Tensor tested = options_.at_goal_test_after_near_bonus ? near : distance;
  return near - options_.at_goal_bonus * (tested < options_.at_goal_radius);
}

std::unique_ptr<RewardTerm> MakeAnalyticReward(const std::string& form,
                                               const TrajectoryObjectiveOptions& options) {
  if (form == kGoalDistanceReward) return std::make_unique<GoalDistanceTerm>(options);
  Fail("unknown analytic reward '{}': expected one of {}", form,
       fmt::join(AnalyticRewardNames(), ", "));
}

}  // namespace cmbrl

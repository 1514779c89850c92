#include "cmbrl/planning/reward_term.h"

#include <fmt/ranges.h>
#include <torch/torch.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

GoalDistanceTerm::GoalDistanceTerm(TrajectoryObjectiveOptions options)
    : options_(std::move(options)) {}

void GoalDistanceTerm::CheckStateSize(int state_dim) const {
  RequireGoalIndexFits(options_, state_dim);
}

torch::Tensor GoalDistanceTerm::Cost(const torch::Tensor&, const torch::Tensor&,
                                     const torch::Tensor& next_states) const {
  const torch::Tensor goal = next_states.narrow(-1, options_.goal_index, 2);
  const torch::Tensor distance = goal.norm(2, -1);
  const torch::Tensor near =
      distance - options_.near_goal_bonus * (distance < options_.near_goal_radius);
  const torch::Tensor tested = options_.at_goal_test_after_near_bonus ? near : distance;
  return near - options_.at_goal_bonus * (tested < options_.at_goal_radius);
}

ObservationRewardTerm::ObservationRewardTerm(std::string form, int offset, int width,
                                             std::vector<double> target, int axis)
    : form_(std::move(form)),
      offset_(offset),
      width_(width),
      target_(std::move(target)),
      axis_(axis) {
  Require(form_ == "site-distance" || form_ == "speed-along" || form_ == "height",
          "unknown observation reward '{}'", form_);
  Require(form_ != "site-distance" || static_cast<int>(target_.size()) == width_,
          "the site-distance target has {} values for a sensor of {}", target_.size(), width_);
  Require(form_ == "site-distance" || (axis_ >= 0 && axis_ < width_),
          "reward axis {} is outside the sensor's {} values", axis_, width_);
}

void ObservationRewardTerm::CheckStateSize(int state_dim) const {
  Require(offset_ >= 0 && offset_ + width_ <= state_dim,
          "the reward reads state components {} to {}: the state has {}", offset_,
          offset_ + width_ - 1, state_dim);
}

torch::Tensor ObservationRewardTerm::Cost(const torch::Tensor&, const torch::Tensor&,
                                          const torch::Tensor& next_states) const {
  const torch::Tensor values = next_states.narrow(-1, offset_, width_);
  if (form_ == "site-distance") {
    const torch::Tensor target =
        torch::tensor(target_, torch::kDouble).to(values.device(), values.scalar_type());
    return (values - target).norm(2, -1);  // a cost: the distance itself
  }
  const torch::Tensor component = values.select(-1, axis_);
  if (form_ == "speed-along") return -component;
  return (component - target_[0]).abs();  // height
}

std::unique_ptr<RewardTerm> MakeAnalyticReward(const std::string& form,
                                               const TrajectoryObjectiveOptions& options) {
  if (form == kGoalDistanceReward) return std::make_unique<GoalDistanceTerm>(options);
  Fail("unknown analytic reward '{}': expected one of {}", form,
       fmt::join(AnalyticRewardNames(), ", "));
}

}  // namespace cmbrl

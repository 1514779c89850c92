#include "cmbrl/planning/trajectory_objective.h"

#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"

namespace cmbrl {

TrajectoryObjective::TrajectoryObjective(const DynamicsModel& dynamics, const CostModel& cost,
                                         Propagation propagation,
                                         TrajectoryObjectiveOptions options)
    : dynamics_(dynamics), cost_(cost), propagation_(propagation), options_(options) {
  Require(dynamics.state_dim() == cost.state_dim(),
          "the dynamics model predicts {} state dimensions, the cost model reads {}",
          dynamics.state_dim(), cost.state_dim());
  ValidateTrajectoryObjectiveOptions(options_, dynamics.state_dim());
}

void TrajectoryObjective::SetState(const torch::Tensor& state) {
  Require(state.dim() == 1 && state.size(0) == dynamics_.state_dim(),
          "planning state has shape {}: expected ({})", c10::str(state.sizes()),
          dynamics_.state_dim());
  state_ = state.to(torch::kFloat);
}

torch::Tensor TrajectoryObjective::StepCost(const torch::Tensor& states) const {
  const torch::Tensor goal = states.narrow(-1, options_.goal_index, 2);
  const torch::Tensor distance = goal.norm(2, -1);
  const torch::Tensor near = distance - options_.near_goal_bonus * (distance < options_.near_goal_radius);
  const torch::Tensor tested = options_.at_goal_test_after_near_bonus ? near : distance;
  return near - options_.at_goal_bonus * (tested < options_.at_goal_radius);
}

ObjectiveValues TrajectoryObjective::Evaluate(const torch::Tensor& actions) {
  Require(state_.defined(), "TrajectoryObjective::Evaluate before SetState");
  Require(actions.dim() == 3 && actions.size(2) == dynamics_.action_dim(),
          "actions have shape {}: expected (N, H, {})", c10::str(actions.sizes()),
          dynamics_.action_dim());
  const torch::NoGradGuard no_grad;
  const std::int64_t members = dynamics_.ensemble_size();
  const std::int64_t samples = actions.size(0), horizon = actions.size(1);
  const std::int64_t state_dim = dynamics_.state_dim();
  const bool per_member = propagation_ == Propagation::kPerMember;

  torch::Tensor state =
      state_.to(actions.device()).view({1, 1, state_dim}).expand({members, samples, state_dim});
  // Per member (E, N) for RCE; one row (1, N) for the mean trajectory.
  torch::Tensor reward = torch::zeros({per_member ? members : 1, samples}, actions.options());
  torch::Tensor constraint = torch::zeros_like(reward);
  last_steps_.clear();
  double reward_discount = 1.0, constraint_discount = 1.0;
  for (std::int64_t t = 0; t < horizon; ++t) {
    const torch::Tensor action =
        actions.select(1, t).unsqueeze(0).expand({members, samples, actions.size(2)});
    torch::Tensor next = dynamics_.PredictUnchecked(state.contiguous(), action.contiguous());
    if (!per_member) next = next.mean(0, /*keepdim=*/true).expand({members, samples, state_dim});
    const torch::Tensor scored = per_member ? next : next.narrow(0, 0, 1);  // (E or 1, N, S)
    reward = reward + reward_discount * StepCost(scored);
    constraint = constraint + constraint_discount * cost_.PredictViolation(scored.contiguous());
    last_steps_.push_back(next);
    state = next;
    reward_discount *= options_.gamma;
    constraint_discount *= per_member ? options_.beta : options_.gamma;
  }
  last_values_ = per_member ? ObjectiveValues{reward.mean(0), std::get<0>(constraint.max(0))}
                            : ObjectiveValues{reward[0], constraint[0]};
  return last_values_;
}

}  // namespace cmbrl

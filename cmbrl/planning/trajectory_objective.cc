#include "cmbrl/planning/trajectory_objective.h"

#include <cmath>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"

namespace cmbrl {

TrajectoryObjective::TrajectoryObjective(const DynamicsModel& dynamics, const CostModel& cost,
                                         Propagation propagation,
                                         TrajectoryObjectiveOptions options,
                                         std::unique_ptr<RewardTerm> reward,
                                         std::unique_ptr<TerminationTerm> termination)
    : dynamics_(dynamics),
      cost_(cost),
      propagation_(propagation),
      options_(options),
      reward_(std::move(reward)),
      termination_(std::move(termination)) {
  Require(reward_ != nullptr, "the planning objective needs a reward term");
  Require(dynamics.state_dim() == cost.state_dim(),
          "the dynamics model predicts {} state dimensions, the cost model reads {}",
          dynamics.state_dim(), cost.state_dim());
  // The goal's place in the state is the goal-distance term's to check: another term reads
  // none.
  ValidateTrajectoryObjectiveOptions(options_, 0);
  reward_->CheckStateSize(dynamics.state_dim());
}

void TrajectoryObjective::SetState(const torch::Tensor& state) {
  Require(state.dim() == 1 && state.size(0) == dynamics_.state_dim(),
          "planning state has shape {}: expected ({})", c10::str(state.sizes()),
          dynamics_.state_dim());
  state_ = state.to(torch::kFloat);
}

torch::Tensor TrajectoryObjective::StepStarts(const torch::Tensor& trajectories) const {
  const torch::Tensor start =
      state_.to(trajectories.device())
          .view({1, 1, 1, -1})
          .expand({1, trajectories.size(1), trajectories.size(2), trajectories.size(3)});
  return torch::cat({start, trajectories.narrow(0, 0, trajectories.size(0) - 1)}, 0);
}

ObjectiveValues TrajectoryObjective::Evaluate(const torch::Tensor& actions) {
  Require(state_.defined(), "TrajectoryObjective::Evaluate before SetState");
  Require(actions.dim() == 3 && actions.size(2) == dynamics_.action_dim(),
          "actions have shape {}: expected (N, H, {})", c10::str(actions.sizes()),
          dynamics_.action_dim());
  const torch::NoGradGuard no_grad;
  const std::int64_t members = dynamics_.ensemble_size();
  const std::int64_t samples = actions.size(0), horizon = actions.size(1);
  const std::int64_t state_dim = dynamics_.state_dim(), action_dim = actions.size(2);
  const bool per_member = propagation_ == Propagation::kPerMember;

  // The rollout is the one sequential part: each step's states come from the one before. Every
  // step's actions are laid out for the ensemble at once, (H, E, N, A).
  const torch::Tensor member_actions = actions.transpose(0, 1)
                                           .unsqueeze(1)
                                           .expand({horizon, members, samples, action_dim})
                                           .contiguous();
  torch::Tensor state =
      state_.to(actions.device()).view({1, 1, state_dim}).expand({members, samples, state_dim});
  std::vector<torch::Tensor> steps;
  steps.reserve(horizon);
  for (std::int64_t t = 0; t < horizon; ++t) {
    torch::Tensor next = dynamics_.PredictUnchecked(state.contiguous(), member_actions[t]);
    if (!per_member) next = next.mean(0, /*keepdim=*/true).expand({members, samples, state_dim});
    steps.push_back(next);
    state = next;
  }
  last_trajectories_ = torch::stack(steps, 0);  // (H, E, N, S)

  // The scores are elementwise in the steps, so they are taken over all H steps at once: the same
  // numbers as step by step, in a few operations instead of a few per step. Per member (H, E, N)
  // for RCE; one row (H, 1, N) for the mean trajectory.
  const torch::Tensor scored =
      per_member ? last_trajectories_ : last_trajectories_.narrow(1, 0, 1).contiguous();
  // Start states and actions, laid out as `scored`, only for the terms that read them: the goal
  // distance does not.
  torch::Tensor starts, step_actions;  // (H, E', N, S), (H, E', N, A)
  if (reward_->reads_states_and_actions() || termination_ != nullptr) {
    starts = StepStarts(scored);
    step_actions = member_actions.narrow(1, 0, scored.size(1));
  }
  torch::Tensor step_rewards = reward_->Cost(starts, step_actions, scored);
  torch::Tensor step_violations = cost_.PredictViolation(scored);
  if (termination_) {
    // A step counts while no step before it ended the episode: 1, then the running product of
    // (1 - terminal) shifted one step.
    const torch::Tensor ongoing = 1 - termination_->Terminal(starts, step_actions, scored);
    const torch::Tensor counted = torch::cat(
        {torch::ones_like(ongoing.narrow(0, 0, 1)), ongoing.narrow(0, 0, horizon - 1).cumprod(0)},
        0);
    step_rewards = step_rewards * counted;
    step_violations = step_violations * counted;
  }
  // sum_t discount^t x_t, added in order of t from zero as a per-step sum would; each discount
  // is rounded to float32 once, as a float tensor times a double scalar is.
  const auto discounted_sum = [&](const torch::Tensor& values, double discount) {
    std::vector<float> factors(horizon);
    double factor = 1.0;
    for (std::int64_t t = 0; t < horizon; ++t, factor *= discount) {
      factors[t] = static_cast<float>(factor);
    }
    const torch::Tensor weighted =
        values * torch::tensor(factors, values.options()).view({horizon, 1, 1});
    torch::Tensor sum = torch::zeros_like(values[0]);
    for (std::int64_t t = 0; t < horizon; ++t) sum = sum + weighted[t];
    return sum;
  };
  const torch::Tensor reward = discounted_sum(step_rewards, options_.gamma);
  const torch::Tensor constraint =
      discounted_sum(step_violations, per_member ? options_.beta : options_.gamma);
  last_values_ = per_member ? ObjectiveValues{reward.mean(0), std::get<0>(constraint.max(0))}
                            : ObjectiveValues{reward[0], constraint[0]};
  return last_values_;
}

}  // namespace cmbrl

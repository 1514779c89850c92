#include "cmbrl/learners/mpc/mpc_agent.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"

namespace cmbrl {

MpcAgent::MpcAgent(const DynamicsModel& dynamics, const CostModel& cost, const std::string& planner,
                   const PlannerSettings& settings, const TrajectoryObjectiveOptions& objective,
                   std::unique_ptr<RewardTerm> reward, std::uint64_t seed,
                   std::unique_ptr<TerminationTerm> termination)
    : dynamics_(dynamics),
      device_(ParseDevice(settings.problem.device, "planner device")),
      horizon_(settings.problem.horizon),
      low_(settings.problem.action_low),
      high_(settings.problem.action_high),
      planner_(MakePlanner(planner, settings, seed)),
      objective_(dynamics, cost, FindPlanner(planner).propagation, objective, std::move(reward),
                 std::move(termination)) {
  Require(settings.problem.action_dim == dynamics.action_dim(),
          "planner action_dim is {}, the dynamics model takes {}", settings.problem.action_dim,
          dynamics.action_dim());
}

void MpcAgent::SetObservation(const std::vector<double>& observation) {
  Require(static_cast<int>(observation.size()) == dynamics_.state_dim(),
          "observation has {} entries, the dynamics model expects {}", observation.size(),
          dynamics_.state_dim());
  RequireFinite(observation, "observation");
  objective_.SetState(torch::tensor(observation, torch::kDouble).to(device_, torch::kFloat));
}

ObjectiveValues MpcAgent::Score(const std::vector<double>& observation,
                                const torch::Tensor& sequences) {
  SetObservation(observation);
  Require(sequences.dim() == 3 && sequences.size(0) >= 1 && sequences.size(1) == horizon_ &&
              sequences.size(2) == dynamics_.action_dim(),
          "sequences of shape {}: expected (N, {}, {}), N >= 1 (the planner's horizon and the "
          "action size)",
          fmt::format("({})", fmt::join(sequences.sizes(), ", ")), horizon_,
          dynamics_.action_dim());
  const torch::Tensor actions = sequences.to(device_, torch::kFloat);
  Require(actions.isfinite().all().item<bool>() && (actions >= low_).all().item<bool>() &&
              (actions <= high_).all().item<bool>(),
          "sequences hold a value outside the action bounds [{}, {}] or a non-finite one", low_,
          high_);
  return objective_.Evaluate(actions);
}

std::vector<double> MpcAgent::Act(const std::vector<double>& observation) {
  const auto start = std::chrono::steady_clock::now();
  SetObservation(observation);
  last_result_ = planner_->Plan(objective_);

  // The one synchronisation: action and figures to the host together.
  const torch::Tensor host =
      torch::cat({last_result_.action.to(torch::kFloat),
                  last_result_.diagnostics.iterations.to(torch::kFloat).view({1}),
                  last_result_.diagnostics.feasible_fraction.view({1}),
                  last_result_.diagnostics.infeasible_elite_fraction.view({1}),
                  last_result_.diagnostics.nonfinite_scores.to(torch::kFloat).view({1})})
          .cpu();
  const float* values = host.data_ptr<float>();
  const int action_dim = dynamics_.action_dim();
  std::vector<double> action(values, values + action_dim);
  Require(values[action_dim + 3] == 0.0f,
          "the learned models predicted NaN or infinity while planning from this state: the plan "
          "is refused rather than executed");
  for (int i = 0; i < action_dim; ++i) {
    Require(std::isfinite(action[i]),
            "the planner produced a non-finite action ({} in entry {}): the learned models "
            "predicted NaN or infinity from this state",
            action[i], i);
  }
  last_plan_.iterations = static_cast<int>(values[action_dim]);
  last_plan_.feasible_fraction = values[action_dim + 1];
  last_plan_.infeasible_elite_fraction = values[action_dim + 2];
  last_plan_.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return action;
}

}  // namespace cmbrl

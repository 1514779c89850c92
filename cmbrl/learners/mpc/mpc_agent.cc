#include "cmbrl/learners/mpc/mpc_agent.h"

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
      planner_(MakePlanner(planner, settings, seed)),
      objective_(dynamics, cost, FindPlanner(planner).propagation, objective, std::move(reward),
                 std::move(termination)) {
  Require(settings.problem.action_dim == dynamics.action_dim(),
          "planner action_dim is {}, the dynamics model takes {}", settings.problem.action_dim,
          dynamics.action_dim());
}

std::vector<double> MpcAgent::Act(const std::vector<double>& observation) {
  const auto start = std::chrono::steady_clock::now();
  Require(static_cast<int>(observation.size()) == dynamics_.state_dim(),
          "observation has {} entries, the dynamics model expects {}", observation.size(),
          dynamics_.state_dim());
  RequireFinite(observation, "observation");
  const torch::Tensor state = torch::tensor(observation, torch::kDouble).to(device_, torch::kFloat);
  objective_.SetState(state);
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

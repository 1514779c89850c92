#include "cmbrl/planning/random_shooting.h"

#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/planning/planning_checks.h"

namespace cmbrl {

RandomShootingPlanner::RandomShootingPlanner(PlanningProblem problem, RandomShootingOptions options,
                                             double penalty, std::uint64_t seed)
    : SeededPlanner(problem.device, seed),
      problem_(std::move(problem)),
      options_(options),
      penalty_(penalty) {
  ValidatePlanningProblem(problem_);
  ValidateRandomShootingOptions(options_);
  ValidatePenalty(penalty_);
}

PlanResult RandomShootingPlanner::Plan(Objective& objective) {
  const torch::NoGradGuard no_grad;
  const double low = problem_.action_low, high = problem_.action_high;
  const torch::Tensor samples =
      torch::rand({options_.samples, problem_.horizon, problem_.action_dim}, generator(),
                  torch::TensorOptions(device()).dtype(torch::kFloat)) *
          (high - low) +
      low;
  const ObjectiveValues values = objective.Evaluate(samples);
  CheckObjectiveValues(values, options_.samples, device());
  const torch::Tensor best = torch::argmin(values.reward_cost + penalty_ * values.constraint_cost);
  PlanResult result;
  result.sequence = samples.index_select(0, best.view({1}))[0];
  result.action = result.sequence[0];
  const torch::Tensor best_constraint = values.constraint_cost.index_select(0, best.view({1}))[0];
  result.diagnostics = {torch::ones({}, torch::TensorOptions(device()).dtype(torch::kLong)),
                        (values.constraint_cost == 0).to(torch::kFloat).mean(),
                        (best_constraint > 0).to(torch::kFloat),
                        values.reward_cost.index_select(0, best.view({1}))[0],
                        AnyNonFinite(values)};
  return result;
}

}  // namespace cmbrl

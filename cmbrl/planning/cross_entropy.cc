#include "cmbrl/planning/cross_entropy.h"

#include <fmt/ranges.h>

#include <cmath>
#include <limits>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/planning/planning_checks.h"
#include "cmbrl/planning/truncated_normal.h"

namespace cmbrl {

CrossEntropyPlanner::CrossEntropyPlanner(PlanningProblem problem, CrossEntropyOptions options,
                                         EliteRule rule, double penalty, std::uint64_t seed)
    : SeededPlanner(problem.device, seed),
      problem_(std::move(problem)),
      options_(options),
      selection_{rule, options_.elites, options_.min_feasible_elites, penalty} {
  ValidatePlanningProblem(problem_);
  ValidateCrossEntropyOptions(options_);
  ValidatePenalty(selection_.penalty);
}

void CrossEntropyPlanner::Reset() { previous_mean_ = torch::Tensor(); }

torch::Tensor CrossEntropyPlanner::CarriedState() const {
  return previous_mean_.defined() ? previous_mean_.cpu().clone() : torch::Tensor();
}

void CrossEntropyPlanner::SetCarriedState(const torch::Tensor& state) {
  if (!state.defined()) {
    previous_mean_ = torch::Tensor();
    return;
  }
  Require(options_.warm_start, "a warm-start mean was given to a planner without warm_start");
  Require(state.dim() == 2 && state.size(0) == problem_.horizon &&
              state.size(1) == problem_.action_dim && state.scalar_type() == torch::kFloat,
          "the warm-start mean is {} of shape ({}): expected float32 of shape ({}, {}) (horizon, "
          "action_dim)",
          c10::toString(state.scalar_type()), fmt::join(state.sizes(), ", "), problem_.horizon,
          problem_.action_dim);
  CheckFinite(state, "the warm-start mean");
  previous_mean_ = state.to(device()).clone();
}

PlanResult CrossEntropyPlanner::Plan(Objective& objective) {
  const torch::NoGradGuard no_grad;
  const auto floats = torch::TensorOptions(device()).dtype(torch::kFloat);
  const std::int64_t horizon = problem_.horizon, action_dim = problem_.action_dim;
  const std::int64_t population = options_.population;
  torch::Tensor mean = torch::zeros({horizon, action_dim}, floats);
  if (options_.warm_start && previous_mean_.defined()) {
    mean.slice(0, 0, horizon - 1).copy_(previous_mean_.slice(0, 1));
  }
  torch::Tensor variance = torch::full({horizon, action_dim}, options_.initial_variance, floats);

  torch::Tensor active = torch::ones({}, floats.dtype(torch::kBool));
  torch::Tensor iterations = torch::zeros({}, floats.dtype(torch::kLong));
  torch::Tensor infeasible_elites = torch::zeros({}, floats);
  torch::Tensor elites_used = torch::zeros({}, floats);
  torch::Tensor feasible_fraction = torch::zeros({}, floats);
  torch::Tensor best_reward_cost = torch::zeros({}, floats);
  torch::Tensor nonfinite = torch::zeros({}, floats.dtype(torch::kBool));
  const double alpha = options_.alpha;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    const torch::Tensor samples =
        SampleTruncatedNormal(mean, variance, population, problem_.action_low, problem_.action_high,
                              generator());  // (N, H, A)
    const ObjectiveValues values = objective.Evaluate(samples);
    CheckObjectiveValues(values, population, device());
    nonfinite = nonfinite | AnyNonFinite(values);
    const EliteMoments elites = ComputeEliteMoments(samples, values, selection_);
    const torch::Tensor& weights = elites.weights;  // (N)
    const torch::Tensor& total = elites.total;
    const torch::Tensor& elite_mean = elites.mean;
    const torch::Tensor& elite_variance = elites.variance;
    mean = torch::where(active, alpha * mean + (1 - alpha) * elite_mean, mean);
    variance = torch::where(active, alpha * variance + (1 - alpha) * elite_variance, variance);

    const torch::Tensor infeasible = (values.constraint_cost > 0).to(torch::kFloat);
    const torch::Tensor counted = active.to(torch::kFloat);
    iterations = iterations + active.to(torch::kLong);
    infeasible_elites = infeasible_elites + counted * (weights * infeasible).sum();
    elites_used = elites_used + counted * total;
    feasible_fraction = torch::where(active, 1 - infeasible.mean(), feasible_fraction);
    const torch::Tensor elite_rewards = torch::where(
        weights > 0, values.reward_cost, torch::full_like(values.reward_cost, INFINITY));
    best_reward_cost = torch::where(active, elite_rewards.min(), best_reward_cost);
    active = active & (variance.max() > options_.epsilon);
  }
  if (options_.warm_start) previous_mean_ = mean;
  PlanResult result;
  result.sequence = mean.clamp(problem_.action_low, problem_.action_high);
  result.action = result.sequence[0];
  result.diagnostics = {iterations, feasible_fraction, infeasible_elites / elites_used,
                        best_reward_cost, nonfinite};
  return result;
}

}  // namespace cmbrl

#include "cmbrl/planning/sample_economy.h"

#include <fmt/ranges.h>

#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/planning/planning_checks.h"

namespace cmbrl {
namespace {

// Each sequence (K, H, A) moved one step earlier; the freed last step repeats the one before it
// (holding an action is the smooth continuation that colored noise favours).
torch::Tensor Shifted(const torch::Tensor& sequences) {
  const std::int64_t h = sequences.size(-2);
  return torch::cat({sequences.narrow(-2, 1, h - 1), sequences.narrow(-2, h - 1, 1)}, -2);
}

// The problem, once it and every option are checked (the noise is built from them).
PlanningProblem Validated(PlanningProblem problem, const CrossEntropyOptions& search,
                          const SampleEconomyOptions& economy, double penalty) {
  ValidatePlanningProblem(problem);
  ValidateCrossEntropyOptions(search);
  ValidateSampleEconomyOptions(economy);
  ValidatePenalty(penalty);
  return problem;
}

}  // namespace

SampleEconomyPlanner::SampleEconomyPlanner(PlanningProblem problem, CrossEntropyOptions search,
                                           SampleEconomyOptions economy, EliteRule rule,
                                           double penalty, std::uint64_t seed)
    : SeededPlanner(problem.device, seed),
      problem_(Validated(std::move(problem), search, economy, penalty)),
      search_(search),
      economy_(economy),
      selection_{rule, search.elites, search.min_feasible_elites, penalty},
      noise_(problem_.horizon, economy_.noise_exponent, device()) {
  populations_ = EconomyPopulations(search_, economy_);
  kept_ = KeptElites(search_, economy_);
}

void SampleEconomyPlanner::Reset() {
  previous_mean_ = torch::Tensor();
  previous_elites_ = torch::Tensor();
}

torch::Tensor SampleEconomyPlanner::CarriedState() const {
  if (!previous_mean_.defined()) return {};
  return torch::cat({previous_mean_.unsqueeze(0), previous_elites_}, 0).cpu().clone();
}

void SampleEconomyPlanner::SetCarriedState(const torch::Tensor& state) {
  if (!state.defined()) {
    Reset();
    return;
  }
  Require(state.dim() == 3 && state.size(0) == 1 + kept_ && state.size(1) == problem_.horizon &&
              state.size(2) == problem_.action_dim && state.scalar_type() == torch::kFloat,
          "the carried plan is {} of shape ({}): expected float32 of shape ({}, {}, {}) (the "
          "mean and {} kept elites, horizon, action_dim)",
          c10::toString(state.scalar_type()), fmt::join(state.sizes(), ", "), 1 + kept_,
          problem_.horizon, problem_.action_dim, kept_);
  CheckFinite(state, "the carried plan");
  const torch::Tensor on_device = state.to(device()).clone();
  previous_mean_ = on_device[0];
  previous_elites_ = on_device.narrow(0, 1, kept_);
}

PlanResult SampleEconomyPlanner::Plan(Objective& objective) {
  const torch::NoGradGuard no_grad;
  const auto floats = torch::TensorOptions(device()).dtype(torch::kFloat);
  const std::int64_t horizon = problem_.horizon, action_dim = problem_.action_dim;
  const double low = problem_.action_low, high = problem_.action_high;
  torch::Tensor mean = torch::zeros({horizon, action_dim}, floats);
  torch::Tensor carried;  // (K, H, A) sequences scored beside the new samples
  if (previous_mean_.defined()) {
    mean.narrow(0, 0, horizon - 1).copy_(previous_mean_.narrow(0, 1, horizon - 1));
    carried = Shifted(previous_elites_);
  }
  torch::Tensor std =
      torch::full({horizon, action_dim}, std::sqrt(search_.initial_variance), floats);

  const double alpha = search_.alpha;
  const int iterations = static_cast<int>(populations_.size());
  torch::Tensor infeasible_elites = torch::zeros({}, floats);
  torch::Tensor elites_used = torch::zeros({}, floats);
  torch::Tensor nonfinite = torch::zeros({}, floats.dtype(torch::kBool));
  torch::Tensor samples, feasible_fraction, best;
  ObjectiveValues values;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const torch::Tensor noise =
        noise_.Sample(populations_[static_cast<size_t>(iteration)], action_dim, generator());
    std::vector<torch::Tensor> parts;
    parts.reserve(3);
    parts.push_back((mean + std * noise).clamp(low, high));  // (n, H, A)
    if (carried.defined() && carried.size(0) > 0) parts.push_back(carried);
    if (iteration == iterations - 1) parts.push_back(mean.clamp(low, high).unsqueeze(0));
    samples = torch::cat(parts, 0);  // (N, H, A)
    const std::int64_t population = samples.size(0);
    values = objective.Evaluate(samples);
    CheckObjectiveValues(values, population, device());
    nonfinite = nonfinite | AnyNonFinite(values);

    const EliteMoments elites = ComputeEliteMoments(samples, values, selection_);
    const torch::Tensor& weights = elites.weights;  // (N)
    const torch::Tensor& total = elites.total;
    // iCEM smooths the spread as a standard deviation (RCE: as a variance).
    mean = alpha * mean + (1 - alpha) * elites.mean;
    std = alpha * std + (1 - alpha) * elites.variance.sqrt();

    const torch::Tensor ranked = RankSamples(values, selection_);  // (N) best first
    carried = samples.index_select(0, ranked.narrow(0, 0, kept_));
    best = ranked.narrow(0, 0, 1);
    const torch::Tensor infeasible = (values.constraint_cost > 0).to(torch::kFloat);
    infeasible_elites = infeasible_elites + (weights * infeasible).sum();
    elites_used = elites_used + total;
    feasible_fraction = 1 - infeasible.mean();
  }
  previous_mean_ = mean;
  previous_elites_ = carried;
  PlanResult result;
  result.sequence = samples.index_select(0, best)[0];
  result.action = result.sequence[0];
  result.diagnostics = {torch::full({}, iterations, floats.dtype(torch::kLong)),
                        feasible_fraction, infeasible_elites / elites_used,
                        values.reward_cost.index_select(0, best)[0], nonfinite};
  return result;
}

}  // namespace cmbrl

#include "cmbrl/planning/elite_rule.h"

#include <cmath>
#include <tuple>

namespace cmbrl {
namespace {

// The order of `key`, lowest first; stable, so ties keep index order on every run.
torch::Tensor StableOrder(const torch::Tensor& key) {
  return std::get<1>(torch::sort(key, /*stable=*/true, /*dim=*/0, /*descending=*/false));
}

}  // namespace

torch::Tensor EliteWeights(const ObjectiveValues& values, const EliteSelection& selection) {
  const std::int64_t n = values.reward_cost.size(0);
  const auto ranks = torch::arange(n, values.reward_cost.options().dtype(torch::kLong));
  const torch::Tensor zeros = torch::zeros_like(values.reward_cost);
  if (selection.rule == EliteRule::kPenalty) {
    const torch::Tensor order =
        StableOrder(values.reward_cost + selection.penalty * values.constraint_cost);
    return zeros.scatter(0, order, (ranks < selection.elites).to(zeros.dtype()));
  }
  const torch::Tensor feasible = values.constraint_cost == 0;
  const torch::Tensor feasible_count = feasible.sum();
  // Enough feasible samples: the best `elites` of them by reward cost.
  const torch::Tensor key =
      torch::where(feasible, values.reward_cost, torch::full_like(values.reward_cost, INFINITY));
  const torch::Tensor by_reward = StableOrder(key);
  const torch::Tensor chosen =
      (ranks < selection.elites) & torch::isfinite(key.index_select(0, by_reward));
  const torch::Tensor enough = zeros.scatter(0, by_reward, chosen.to(zeros.dtype()));
  // Too few: every feasible sample, plus the first (min - feasible) by constraint cost.
  const torch::Tensor by_constraint = StableOrder(values.constraint_cost);
  const torch::Tensor padding = (ranks < selection.min_feasible_elites - feasible_count);
  const torch::Tensor too_few =
      feasible.to(zeros.dtype()).index_add(0, by_constraint, padding.to(zeros.dtype()));
  return torch::where(feasible_count >= selection.min_feasible_elites, enough, too_few);
}

EliteMoments ComputeEliteMoments(const torch::Tensor& samples, const ObjectiveValues& values,
                                 const EliteSelection& selection) {
  EliteMoments moments;
  moments.weights = EliteWeights(values, selection);
  moments.total = moments.weights.sum();
  const torch::Tensor w = moments.weights.view({samples.size(0), 1, 1});
  moments.mean = (w * samples).sum(0) / moments.total;
  moments.variance = (w * (samples - moments.mean).pow(2)).sum(0) / moments.total;
  return moments;
}

torch::Tensor RankSamples(const ObjectiveValues& values, const EliteSelection& selection) {
  if (selection.rule == EliteRule::kPenalty) {
    return StableOrder(values.reward_cost + selection.penalty * values.constraint_cost);
  }
  // Two stable sorts make a lexicographic order: by reward cost, then by constraint cost (0 for
  // every feasible sample, so the feasible keep their reward order ahead of all the others).
  const torch::Tensor by_reward = StableOrder(values.reward_cost);
  const torch::Tensor then_by_constraint =
      StableOrder(values.constraint_cost.index_select(0, by_reward));
  return by_reward.index_select(0, then_by_constraint);
}

}  // namespace cmbrl

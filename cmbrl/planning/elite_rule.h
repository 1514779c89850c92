// How a cross-entropy search chooses its elites from a scored population: the one place where
// CEM and RCE differ (paper Section IV-B, Algorithm 1; facts B5), shared by every search that
// refits a distribution to elites (cross_entropy.h, sample_economy.h).
#pragma once

#include <torch/torch.h>

#include <cstdint>

#include "cmbrl/planning/planner.h"

namespace cmbrl {

enum class EliteRule {
  kPenalty,  // CEM: the `elites` lowest reward_cost + penalty * constraint_cost
  kRobust,   // RCE: the `elites` feasible samples with the lowest reward cost; with fewer than
             // min_feasible_elites feasible, those plus the first (min - feasible) samples by
             // constraint cost (feasible ones sort first, so they can count twice)
};

struct EliteSelection {
  EliteRule rule = EliteRule::kRobust;
  int elites = 12;
  int min_feasible_elites = 5;  // kRobust only
  double penalty = 0.0;         // kPenalty only: the constraint cost's weight
};

// Elite weights (N) for scores of N >= selection.elites samples: how often each sample counts
// among the elites. On the scores' device; no value is read back to the host.
torch::Tensor EliteWeights(const ObjectiveValues& values, const EliteSelection& selection);

// The elites' weighted statistics over a population: what a cross-entropy search refits to.
struct EliteMoments {
  torch::Tensor weights;   // (N) EliteWeights
  torch::Tensor total;     // () their sum: the elites counted
  torch::Tensor mean;      // (H, A) the elites' weighted mean
  torch::Tensor variance;  // (H, A) their weighted variance about it
};

// The elites of `samples` (N, H, A), scored as `values`, and their moments. No host read.
EliteMoments ComputeEliteMoments(const torch::Tensor& samples, const ObjectiveValues& values,
                                 const EliteSelection& selection);

// Indices (N) of the samples, best first, in the rule's own order: by the penalised score
// (kPenalty); feasible samples by reward cost, then the infeasible by constraint cost and, among
// equal constraint costs, by reward cost (kRobust). Ties keep index order, so every run ranks
// alike. The first is the sample a planner that acts on its best sample executes.
torch::Tensor RankSamples(const ObjectiveValues& values, const EliteSelection& selection);

}  // namespace cmbrl

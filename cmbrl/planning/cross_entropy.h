// The cross-entropy method and the Robust Cross-Entropy method (paper Section IV-B, Algorithm 1;
// facts B5). They share sampling and update and differ only in how elites are chosen.
#pragma once

#include <cstdint>

#include "cmbrl/planning/elite_rule.h"
#include "cmbrl/planning/planner.h"

namespace cmbrl {

// Samples a truncated normal over (H, A), scores with the objective, refits mean and variance to
// the elites with smoothing, and stops after max_iterations or once every variance is at most
// epsilon. Elites are weights over the population, so no step reads a value back to the host:
// converged iterations are masked instead of skipped. Acts with the first action of the final
// mean. Not thread-safe.
class CrossEntropyPlanner final : public SeededPlanner {
 public:
  // `penalty` weighs the constraint cost in kPenalty's score (PlannerSettings::penalty); kRobust
  // reads none. Throws cmbrl::Error for bad options, penalty or problem.
  CrossEntropyPlanner(PlanningProblem problem, CrossEntropyOptions options, EliteRule rule,
                      double penalty, std::uint64_t seed);

  PlanResult Plan(Objective& objective) override;
  void Reset() override;
  // The warm-start mean (H, A) as float32 on the host, or undefined.
  torch::Tensor CarriedState() const override;
  void SetCarriedState(const torch::Tensor& state) override;

 private:
  PlanningProblem problem_;
  CrossEntropyOptions options_;
  EliteSelection selection_;
  torch::Tensor previous_mean_;  // (H, A), warm start only
};

}  // namespace cmbrl

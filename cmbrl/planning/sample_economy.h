// A constraint-aware planner that needs a fraction of RCE's samples: RCE's feasibility rule
// (paper Algorithm 1: elites from the feasible set, the least violating when too few are
// feasible; elite_rule.h) inside iCEM's sample economy (Pinneri et al., "Sample-efficient
// Cross-Entropy Method for Real-time Planning", CoRL 2020):
//   - colored noise: the sequences are temporally correlated (colored_noise.h), clipped to the box;
//   - memory: a share of the elites is carried into the next iteration, and at the next plan
//     shifted by one step into its first iteration;
//   - a population that shrinks by population_decay each iteration;
//   - the distribution's mean is scored among the last iteration's samples, and the planner acts
//     on the best sample by the elite rule's order (elite_rule.h RankSamples), not on the mean.
// The mean is shifted from plan to plan (its last step starts at 0), the spread starts afresh.
// A new planner beside RCE, which it does not change.
#pragma once

#include <cstdint>
#include <vector>

#include "cmbrl/planning/colored_noise.h"
#include "cmbrl/planning/elite_rule.h"
#include "cmbrl/planning/planner.h"

namespace cmbrl {

// Not thread-safe: it owns its generator and the state carried from plan to plan.
class SampleEconomyPlanner final : public SeededPlanner {
 public:
  // Throws cmbrl::Error for bad options, penalty or problem.
  SampleEconomyPlanner(PlanningProblem problem, CrossEntropyOptions search,
                       SampleEconomyOptions economy, EliteRule rule, double penalty,
                       std::uint64_t seed);

  PlanResult Plan(Objective& objective) override;
  void Reset() override;
  // The last plan's mean and kept elites, stacked (1 + kept, H, A) as float32 on the host, or
  // undefined before the first plan of an episode.
  torch::Tensor CarriedState() const override;
  void SetCarriedState(const torch::Tensor& state) override;

 private:
  PlanningProblem problem_;
  CrossEntropyOptions search_;
  SampleEconomyOptions economy_;
  EliteSelection selection_;
  std::vector<std::int64_t> populations_;  // new samples at each iteration
  int kept_ = 0;                           // elites carried from one iteration to the next
  ColoredNoise noise_;
  torch::Tensor previous_mean_;    // (H, A) the last plan's final mean
  torch::Tensor previous_elites_;  // (kept, H, A) the last plan's best samples
};

}  // namespace cmbrl

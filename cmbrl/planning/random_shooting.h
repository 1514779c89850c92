// Random shooting MPC, the paper's MPC-random baseline (Section IV-C; facts B5).
#pragma once

#include <cstdint>

#include "cmbrl/planning/planner.h"

namespace cmbrl {

// Draws uniform sequences in the action box and acts with the first action of the best one.
// Not thread-safe.
class RandomShootingPlanner final : public SeededPlanner {
 public:
  // `penalty` weighs the constraint cost in a sample's score (PlannerSettings::penalty). Throws
  // cmbrl::Error for bad options, penalty or problem.
  RandomShootingPlanner(PlanningProblem problem, RandomShootingOptions options, double penalty,
                        std::uint64_t seed);

  PlanResult Plan(Objective& objective) override;

 private:
  PlanningProblem problem_;
  RandomShootingOptions options_;
  double penalty_;
};

}  // namespace cmbrl

#include "cmbrl/planning/planning_checks.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

void ValidatePlanningProblem(const PlanningProblem& p) {
  Require(p.horizon >= 1 && p.horizon <= 1000, "horizon is {}: expected 1 to 1000 steps",
          p.horizon);
  Require(p.action_dim >= 1, "action_dim is {}: expected at least 1", p.action_dim);
  Require(
      std::isfinite(p.action_low) && std::isfinite(p.action_high) && p.action_low < p.action_high,
      "action bounds [{}, {}]: expected finite numbers with low < high", p.action_low,
      p.action_high);
}

void CheckObjectiveValues(const ObjectiveValues& values, std::int64_t count,
                          const torch::Device& device) {
  for (const torch::Tensor* t : {&values.reward_cost, &values.constraint_cost}) {
    const char* name = t == &values.reward_cost ? "reward_cost" : "constraint_cost";
    Require(t->defined() && t->dim() == 1 && t->size(0) == count,
            "objective {} has shape {}: expected ({})", name,
            t->defined() ? c10::str(t->sizes()) : "undefined", count);
    Require(t->scalar_type() == torch::kFloat && t->device() == device,
            "objective {} must be float32 on {}", name, device.str());
  }
}

torch::Tensor AnyNonFinite(const ObjectiveValues& values) {
  return torch::logical_not(torch::isfinite(values.reward_cost).all() &
                            torch::isfinite(values.constraint_cost).all());
}

}  // namespace cmbrl

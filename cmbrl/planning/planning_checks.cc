#include "cmbrl/planning/planning_checks.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

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

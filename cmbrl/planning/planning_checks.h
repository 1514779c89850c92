// Checks shared by the planners.
#pragma once

#include <cstdint>

#include "cmbrl/planning/planner.h"

namespace cmbrl {

// Throws cmbrl::Error unless both scores are float32 (count) on `device`.
void CheckObjectiveValues(const ObjectiveValues& values, std::int64_t count,
                          const torch::Device& device);

// () bool on the scores' device: whether any score is NaN or infinite. No synchronisation.
torch::Tensor AnyNonFinite(const ObjectiveValues& values);

}  // namespace cmbrl

// What a planner needs from a learned constraint model (paper Section IV-A): whether a state
// violates a constraint.
#pragma once

#include <cstdint>
#include <vector>

#include "cmbrl/models/tensor_fwd.h"

namespace cmbrl {

// Classifies states as violating (1) or not (0). Concurrent predictions on one model are safe
// unless a class comment says otherwise.
class CostModel {
 public:
  virtual ~CostModel() = default;

  virtual int state_dim() const = 0;

  // states (..., S) float32 on any device -> (...) float32 0/1 on the same device. No host
  // synchronisation; shapes are checked, values are not (see PredictRows).
  virtual torch::Tensor PredictViolation(const torch::Tensor& states) const = 0;

  // states: `rows` rows of state_dim floats on the host -> one 0/1 per row. Throws cmbrl::Error
  // for a non-finite value, naming the row and column.
  virtual std::vector<std::uint8_t> PredictRows(const float* states, int rows) const = 0;
};

}  // namespace cmbrl

// What a planner needs from a learned dynamics model (paper Section IV-A).
#pragma once

#include "cmbrl/models/tensor_fwd.h"

namespace cmbrl {

// Predicts next states for a batch of (member, sample) pairs, each member of an ensemble with its
// own input. Implementations keep their weights constant while predicting; concurrent Predict
// calls on one model are safe unless a class comment says otherwise.
class DynamicsModel {
 public:
  virtual ~DynamicsModel() = default;

  virtual int state_dim() const = 0;
  virtual int action_dim() const = 0;
  virtual int ensemble_size() const = 0;

  // states (E, N, S) and actions (E, N, A), float32 on the model's device -> next states
  // (E, N, S) there. Checks shapes, device and that the inputs are finite (one host
  // synchronisation); throws cmbrl::Error naming what is wrong.
  virtual torch::Tensor Predict(const torch::Tensor& states,
                                const torch::Tensor& actions) const = 0;

  // The same without the finiteness check: no host synchronisation, for the planning hot path,
  // whose caller checks its final result instead.
  virtual torch::Tensor PredictUnchecked(const torch::Tensor& states,
                                         const torch::Tensor& actions) const = 0;
};

}  // namespace cmbrl

// Dynamics whose state holds the previous action (environment.previous_action): those
// components of a next state are the action just taken, known exactly, so the planner's
// predictions carry the action itself there rather than the network's estimate of it.
#pragma once

#include "cmbrl/models/dynamics_model.h"

namespace cmbrl {

// Wraps a model (borrowed: it outlives this) whose states hold the previous action in the A
// components from `offset` on: its predictions with the actions written there. Safe to call
// concurrently where the wrapped model is.
class ActionEchoDynamics final : public DynamicsModel {
 public:
  // Throws cmbrl::Error for an offset where A components do not fit in the state.
  ActionEchoDynamics(const DynamicsModel& model, int offset);

  int state_dim() const override { return model_.state_dim(); }
  int action_dim() const override { return model_.action_dim(); }
  int ensemble_size() const override { return model_.ensemble_size(); }
  int offset() const { return offset_; }

  // states (E, N, S), actions (E, N, A) -> next states (E, N, S), as the wrapped model's, with
  // next[..., offset:offset + A] = actions.
  torch::Tensor Predict(const torch::Tensor& states, const torch::Tensor& actions) const override;
  torch::Tensor PredictUnchecked(const torch::Tensor& states,
                                 const torch::Tensor& actions) const override;

 private:
  torch::Tensor Echo(torch::Tensor next, const torch::Tensor& actions) const;

  const DynamicsModel& model_;
  int offset_;
};

}  // namespace cmbrl

// The paper's planning objective (Section IV-B; facts B2): roll the learned dynamics forward
// under each action sequence, score the goal distance analytically and the constraint with the
// learned classifier.
#pragma once

#include "cmbrl/models/cost_model.h"
#include "cmbrl/models/dynamics_model.h"
#include "cmbrl/planning/planner.h"

namespace cmbrl {

// Scores (N, H, A) action sequences from the current state. d_t is the goal distance of the
// predicted state minus the bonuses. Borrows the models, which must outlive it; not thread-safe.
class TrajectoryObjective final : public Objective {
 public:
  TrajectoryObjective(const DynamicsModel& dynamics, const CostModel& cost, Propagation propagation,
                      TrajectoryObjectiveOptions options);

  // The state to plan from: (S) float32 on the models' device.
  void SetState(const torch::Tensor& state);

  ObjectiveValues Evaluate(const torch::Tensor& actions) override;

  // Predicted states of the last Evaluate: (E, N, H, S); with kEnsembleMean every member holds
  // the mean trajectory. For pictures of the planner's predictions.
  torch::Tensor last_trajectories() const { return last_trajectories_.permute({1, 2, 0, 3}); }
  // Scores of the last Evaluate, (N) each.
  const ObjectiveValues& last_values() const { return last_values_; }

 private:
  torch::Tensor StepCost(const torch::Tensor& states) const;  // (..., S) -> (...)

  const DynamicsModel& dynamics_;
  const CostModel& cost_;
  Propagation propagation_;
  TrajectoryObjectiveOptions options_;
  torch::Tensor state_;
  torch::Tensor last_trajectories_;  // (H, E, N, S) of the last Evaluate
  ObjectiveValues last_values_;
};

}  // namespace cmbrl

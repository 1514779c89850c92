// The paper's planning objective (Section IV-B; facts B2): roll the learned dynamics forward
// under each action sequence, score every predicted step with the run's reward term (the Goal
// tasks' goal distance, analytically) and the constraint with the learned classifier.
#pragma once

#include <memory>

#include "cmbrl/models/cost_model.h"
#include "cmbrl/models/dynamics_model.h"
#include "cmbrl/planning/planner.h"
#include "cmbrl/planning/reward_term.h"

namespace cmbrl {

// Scores (N, H, A) action sequences from the current state. d_t is the reward term's cost of
// the predicted step. Borrows the models, which must outlive it, and owns the reward term; not
// thread-safe.
class TrajectoryObjective final : public Objective {
 public:
  // `termination`, when given, cuts both discounted sums after a predicted terminal step (the
  // terminal step itself counts). Throws cmbrl::Error for models of different state sizes, bad
  // options or no reward term.
  TrajectoryObjective(const DynamicsModel& dynamics, const CostModel& cost, Propagation propagation,
                      TrajectoryObjectiveOptions options, std::unique_ptr<RewardTerm> reward,
                      std::unique_ptr<TerminationTerm> termination = nullptr);

  // The state to plan from: (S) float32 on the models' device.
  void SetState(const torch::Tensor& state);

  ObjectiveValues Evaluate(const torch::Tensor& actions) override;

  // Predicted states of the last Evaluate: (E, N, H, S); with kEnsembleMean every member holds
  // the mean trajectory. For pictures of the planner's predictions.
  torch::Tensor last_trajectories() const { return last_trajectories_.permute({1, 2, 0, 3}); }
  // Scores of the last Evaluate, (N) each.
  const ObjectiveValues& last_values() const { return last_values_; }

 private:
  // Each step's start states, laid out as `trajectories` (H, E', N, S): the planning state, then
  // the step before's prediction.
  torch::Tensor StepStarts(const torch::Tensor& trajectories) const;

  const DynamicsModel& dynamics_;
  const CostModel& cost_;
  Propagation propagation_;
  TrajectoryObjectiveOptions options_;
  std::unique_ptr<RewardTerm> reward_;
  std::unique_ptr<TerminationTerm> termination_;  // none: no step ends the episode
  torch::Tensor state_;
  torch::Tensor last_trajectories_;  // (H, E, N, S) of the last Evaluate
  ObjectiveValues last_values_;
};

}  // namespace cmbrl

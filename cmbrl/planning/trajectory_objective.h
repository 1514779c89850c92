// The paper's planning objective (Section IV-B; facts B2): roll the learned dynamics forward
// under each action sequence, score the goal distance analytically and the constraint with the
// learned classifier.
#pragma once

#include <vector>

#include "cmbrl/models/cost_model.h"
#include "cmbrl/models/dynamics_model.h"
#include "cmbrl/planning/planner.h"

namespace cmbrl {

struct TrajectoryObjectiveOptions {
  int goal_index = 6;             // state[goal_index], state[goal_index + 1]: goal in ego XY
  double gamma = 0.98;            // discount of the reward cost (and of CEM's constraint cost)
  double beta = 0.4;              // RCE: discount of the constraint count
  double near_goal_radius = 0.2;  // m: a predicted state this close earns near_goal_bonus
  double near_goal_bonus = 5.0;
  double at_goal_radius = 0.1;  // m: and this close a further at_goal_bonus
  double at_goal_bonus = 8.0;
  // The original's code tests at_goal_radius on the distance already lowered by
  // near_goal_bonus, so every d < near_goal_radius earns both bonuses (facts B2: d - 13 below
  // 0.2, which is what produced Table I). false: the written rule, at_goal_bonus only below
  // at_goal_radius.
  bool at_goal_test_after_near_bonus = true;
};

// Throws cmbrl::Error naming the first bad field.
void ValidateTrajectoryObjectiveOptions(const TrajectoryObjectiveOptions& options, int state_dim);

enum class Propagation {
  // CEM and random: one trajectory from the ensemble-mean prediction; reward cost
  // sum_t gamma^t d_t, constraint cost sum_t gamma^t unsafe_t (the planner adds the penalty).
  kEnsembleMean,
  // RCE: every member rolls its own trajectory (TS-infinity); reward cost is the members' mean of
  // sum_t gamma^t d_t, constraint cost the members' max of sum_t beta^t unsafe_t.
  kPerMember,
};

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
  // the mean trajectory. For pictures of the planner's predictions: stacked only when asked, so
  // planning pays nothing for it.
  torch::Tensor last_trajectories() const { return torch::stack(last_steps_, 2); }
  // Scores of the last Evaluate, (N) each.
  const ObjectiveValues& last_values() const { return last_values_; }

 private:
  torch::Tensor StepCost(const torch::Tensor& states) const;  // (..., S) -> (...)

  const DynamicsModel& dynamics_;
  const CostModel& cost_;
  Propagation propagation_;
  TrajectoryObjectiveOptions options_;
  torch::Tensor state_;
  std::vector<torch::Tensor> last_steps_;  // H tensors (E, N, S) of the last Evaluate
  ObjectiveValues last_values_;
};

}  // namespace cmbrl

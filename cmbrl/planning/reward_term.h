// The reward term of the planning objective (paper Section IV-B: d_t of every predicted step), as
// a cost to minimise. Which one a run plans with is its config's objective.reward; an analytic
// term is its task's own form (env/task_list.h names it, AnalyticRewardNames() lists the forms).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cmbrl/models/tensor_fwd.h"
#include "cmbrl/planning/planning_options.h"

namespace cmbrl {

// Batched over any leading shape. Implementations are immutable once built: thread-safe.
class RewardTerm {
 public:
  virtual ~RewardTerm() = default;
  // The cost of each predicted step from `states` (..., S) under `actions` (..., A) to
  // `next_states` (..., S): (...). The objective may pass undefined states and actions to a term
  // that does not read them (reads_states_and_actions() false).
  virtual torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                             const torch::Tensor& next_states) const = 0;
  // Whether Cost reads `states` and `actions` (the objective then stacks them for it).
  virtual bool reads_states_and_actions() const = 0;
  // Throws cmbrl::Error naming what the term reads that a state of `state_dim` values lacks.
  virtual void CheckStateSize(int state_dim) const { (void)state_dim; }
};

// The Goal tasks' analytic term ("goal-distance", facts B2): the distance of the goal in the
// predicted state's ego frame (next_states[goal_index], next_states[goal_index + 1]) minus the
// near- and at-goal bonuses of `options`.
class GoalDistanceTerm final : public RewardTerm {
 public:
  explicit GoalDistanceTerm(TrajectoryObjectiveOptions options);
  torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                     const torch::Tensor& next_states) const override;
  bool reads_states_and_actions() const override { return false; }
  void CheckStateSize(int state_dim) const override;

 private:
  TrajectoryObjectiveOptions options_;
};

// A declared task's reward (env/mujoco_task_options.h) on the predicted next state's components
// [offset, offset + width) of one sensor: "site-distance" (minus the distance to `target`),
// "speed-along" (component `axis`) or "height" (minus |component `axis` - target[0]|). The
// environment computes the same on its observation (ObservationReward in env/mujoco_task.h).
class ObservationRewardTerm final : public RewardTerm {
 public:
  ObservationRewardTerm(std::string form, int offset, int width, std::vector<double> target,
                        int axis);
  torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                     const torch::Tensor& next_states) const override;
  bool reads_states_and_actions() const override { return false; }
  void CheckStateSize(int state_dim) const override;

 private:
  std::string form_;
  int offset_, width_;
  std::vector<double> target_;
  int axis_;
};

// Where a predicted step ends the episode (a task's termination signal, objective.termination):
// the objective's discounted sums count no step after it. Batched; thread-safe once built.
class TerminationTerm {
 public:
  virtual ~TerminationTerm() = default;
  // 1 where the step from `states` (..., S) under `actions` (..., A) to `next_states` (..., S)
  // ends the episode, 0 elsewhere: (...) float32.
  virtual torch::Tensor Terminal(const torch::Tensor& states, const torch::Tensor& actions,
                                 const torch::Tensor& next_states) const = 0;
};

// The analytic term called `form` (one of AnalyticRewardNames()) with the objective's options.
// Throws cmbrl::Error naming an unknown form and the known ones.
std::unique_ptr<RewardTerm> MakeAnalyticReward(const std::string& form,
                                               const TrajectoryObjectiveOptions& options);

}  // namespace cmbrl

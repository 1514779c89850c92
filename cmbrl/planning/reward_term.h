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

// Where a lidar block lies in the state and how to read it (Safety Gym's pseudo-lidar: a reading
// of max(0, max_dist - d) / max_dist in the bin of the object's angle, and alias x reading in the
// next bin).
struct LidarBlock {
  int offset = 0;  // state[offset] is the block's bin 0
  int bins = 16;
  double max_dist = 0.0;  // m: the task's lidar range
};

// What the lidar forms must know of the task, which only its spec holds (env/tasks/task_spec.h;
// the planner knows no task): how far its lidars see and Circle's radius.
struct LidarGeometry {
  double max_dist = 0.0;       // m
  double circle_radius = 0.0;  // m
};

// The stock tasks' analytic terms on their lidar observation, which recovers a lone object's
// distance (max_dist x (1 - the largest reading)) and its ego angle ((bin + alias) x 2 pi / bins,
// alias = next bin's reading / the largest):
// - "goal-lidar-distance" (Button, stock Goal): the goal's distance minus the goal-distance
//   form's near- and at-goal bonuses;
// - "push-lidar-distances" (Push): the robot's distance to the box plus the box's to the goal
//   (from both objects' ego positions), whose decrease is Safety-Gymnasium's dense reward;
// - "circle-lidar-speed" (Circle): minus 0.1 x the speed around the ring's centre / (1 + |r -
//   radius|), the ring's centre read from its lidar and the velocity from the velocimeter.
// Beyond max_dist an object reads as max_dist away.
class LidarRewardTerm final : public RewardTerm {
 public:
  // `blocks` in the form's order: goal (goal-lidar-distance); push box, goal
  // (push-lidar-distances); circle (circle-lidar-speed), whose `velocimeter` is the offset of
  // the velocimeter's x (then y).
  LidarRewardTerm(std::string form, std::vector<LidarBlock> blocks, int velocimeter,
                  TrajectoryObjectiveOptions options, double circle_radius);
  torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                     const torch::Tensor& next_states) const override;
  bool reads_states_and_actions() const override { return false; }
  void CheckStateSize(int state_dim) const override;

 private:
  std::string form_;
  std::vector<LidarBlock> blocks_;
  int velocimeter_;
  TrajectoryObjectiveOptions options_;
  double circle_radius_;
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

// The analytic term called `form` (one of AnalyticRewardNames()) with the objective's options,
// for states whose components are called `observation_names` (the lidar forms find their blocks
// there: "goal_lidar_0", "push_box_lidar_0", "circle_lidar_0", "velocimeter_x"). Throws
// cmbrl::Error naming an unknown form and the known ones, or a block the observation lacks.
// `geometry`, the task's, is read by the lidar forms only (they refuse a range that is not
// positive).
std::unique_ptr<RewardTerm> MakeAnalyticReward(const std::string& form,
                                               const TrajectoryObjectiveOptions& options,
                                               const std::vector<std::string>& observation_names,
                                               const LidarGeometry& geometry = {});

}  // namespace cmbrl

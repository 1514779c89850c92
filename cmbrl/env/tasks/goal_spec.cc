#include "cmbrl/env/tasks/goal_spec.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

GoalTaskSpec MakeGoalTaskSpec(const TaskEntry& task, Variant variant) {
  const RobotKind robot = task.robot;
  const int level = task.level;
  Require(level == 1 || level == 2,
          "task '{}': Goal task level {} is not supported: expected 1 or 2", task.name, level);
  const bool paper = IsPaperWorld(variant);
  GoalTaskSpec spec;
  spec.robot = robot;
  spec.level = level;
  spec.variant = variant;
  spec.name = task.name;

  const double half_width = level == 1 ? 1.5 : 2.0;
  spec.placement = {-half_width, -half_width, half_width, half_width};
  if (paper) {
    spec.num_hazards = level == 1 ? 7 : 14;
    spec.num_vases = level == 1 ? 1 : 2;
    spec.vases_constrained = true;
    spec.goal_keepout = 0.35;
    spec.vase_velocity_threshold = 1e-3;
    spec.action_repeat = robot == RobotKind::kPoint ? 3 : 2;
    // 30 s of simulated time: 300 env steps of 0.1 s (Point), 150 of 0.2 s (rover).
    spec.max_env_steps = robot == RobotKind::kPoint ? 300 : 150;
    spec.observation = ObservationKind::kEgoState;
    if (variant == Variant::kPaperLidar) {
      // safety-starter-agents stepped the modified env itself: one env step per agent step,
      // episodes of 300 (Point) or 150 (Car) env steps, Safety Gym's observation.
      spec.action_repeat = 1;
      spec.observation = ObservationKind::kLidarSorted;
    }
  } else {
    spec.num_hazards = level == 1 ? 8 : 10;
    spec.num_vases = level == 1 ? 1 : 10;
    spec.vases_constrained = level == 2;
    spec.goal_keepout = 0.305;
    spec.vase_velocity_threshold = 1e-4;
    spec.action_repeat = 1;
    spec.max_env_steps = 1000;
    spec.observation = ObservationKind::kLidar;
  }
  return spec;
}

int ObservationSize(const GoalTaskSpec& spec) {
  if (spec.observation == ObservationKind::kEgoState) {
    return 8 + 2 * (spec.num_vases + spec.num_hazards);
  }
  // accelerometer, gyro, magnetometer, velocimeter; the stock car's ball joint (3 + 9; the
  // paper's rover has no joint sensors); lidars.
  const bool stock_car = spec.robot == RobotKind::kCar && !IsPaperWorld(spec.variant);
  const int sensors = 12 + (stock_car ? 12 : 0);
  const int lidars = 1 + (spec.num_hazards > 0) + (spec.num_vases > 0);
  return sensors + lidars * spec.lidar_bins;
}

GoalTaskSpec GoalTaskSpecByName(const std::string& task, Variant variant) {
  return MakeGoalTaskSpec(FindTask(task), variant);
}

}  // namespace cmbrl

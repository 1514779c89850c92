#include "cmbrl/env/tasks/task_spec.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

// Facts A1 to A6, B0, B1: the paper's modified Goal tasks and the stock ones.
void FillGoal(NavigationTaskSpec& spec) {
  const int level = spec.level;
  const bool paper = IsPaperWorld(spec.variant);
  const double half_width = level == 1 ? 1.5 : 2.0;
  spec.placement = {-half_width, -half_width, half_width, half_width};
  if (paper) {
    spec.num_hazards = level == 1 ? 7 : 14;
    spec.num_vases = level == 1 ? 1 : 2;
    spec.vases_constrained = true;
    spec.goal_keepout = 0.35;
    spec.vase_velocity_threshold = 1e-3;
    spec.action_repeat = spec.robot == RobotKind::kPoint ? 3 : 2;
    // 30 s of simulated time: 300 env steps of 0.1 s (Point), 150 of 0.2 s (rover).
    spec.max_env_steps = spec.robot == RobotKind::kPoint ? 300 : 150;
    spec.observation = ObservationKind::kEgoState;
    if (spec.variant == Variant::kPaperLidar) {
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
  }
}

// button/button_level{0,1,2}.py: 4 buttons and a goal marker of twice a button's size on the goal
// one; level 1 adds 4 hazards (keep-out 0.18) and 4 gremlins, and constrains the buttons; level 2
// has 8 hazards and 6 gremlins. The Goal object keeps its default keep-out, 0.4.
void FillButton(NavigationTaskSpec& spec) {
  const double half_width = spec.level == 0 ? 1.0 : spec.level == 1 ? 1.5 : 1.8;
  spec.placement = {-half_width, -half_width, half_width, half_width};
  spec.num_buttons = 4;
  spec.goal_size = 2 * spec.button_size;
  spec.goal_keepout = 0.4;
  if (spec.level >= 1) {
    spec.buttons_constrained = true;
    spec.num_hazards = spec.level == 1 ? 4 : 8;
    spec.hazard_keepout = 0.18;
    spec.num_gremlins = spec.level == 1 ? 4 : 6;
  }
}

// push/push_level{0,1,2}.py and push_box.py: a goal and the box (the Car's smaller and lighter);
// level 1 adds 2 hazards of radius 0.3 and an unconstrained pillar; level 2 has 4 hazards and 4
// constrained pillars. Hazards and the goal keep their default keep-out, 0.4.
void FillPush(NavigationTaskSpec& spec) {
  const double half_width = spec.level == 0 ? 1.0 : spec.level == 1 ? 1.5 : 2.0;
  spec.placement = {-half_width, -half_width, half_width, half_width};
  spec.goal_keepout = 0.4;
  spec.push_box = true;
  if (spec.robot == RobotKind::kCar) {
    spec.box_size = 0.125;
    spec.box_keepout = 0.125;
    spec.box_density = 0.0005;
  }
  if (spec.level >= 1) {
    spec.num_hazards = spec.level == 1 ? 2 : 4;
    spec.hazard_size = 0.3;
    spec.hazard_keepout = 0.4;
    spec.num_pillars = spec.level == 1 ? 1 : 4;
    spec.pillars_constrained = spec.level == 2;
  }
}

// circle/circle_level{0,1,2}.py, circle.py, sigwalls.py: the ring at the origin, the robot drawn in
// [-0.8, 0.8]^2 with no keep-out, 500-step episodes, a 6 m lidar; walls at x = +-1.125 (level 1)
// and y = +-1.125 too (level 2).
void FillCircle(NavigationTaskSpec& spec) {
  spec.placement = {-1.5, -1.5, 1.5, 1.5};  // what pictures show: the ring
  spec.robot_placement_own = true;
  spec.robot_placement = {-0.8, -0.8, 0.8, 0.8};
  spec.robot_keepout = 0.0;
  spec.circle = true;
  spec.max_env_steps = 500;
  spec.lidar_max_dist = 6.0;
  spec.num_sigwalls = spec.level == 0 ? 0 : spec.level == 1 ? 2 : 4;
}

}  // namespace

NavigationTaskSpec MakeNavigationTaskSpec(const TaskEntry& task, Variant variant) {
  const int min_level = task.family == TaskFamily::kGoal ? 1 : 0;
  Require(task.level >= min_level && task.level <= 2,
          "task '{}': {} task level {} is not supported: expected {} to 2", task.name,
          FamilyName(task.family), task.level, min_level);
  Require(HasPaperVariant(task) || !IsPaperWorld(variant),
          "task '{}' has no variant '{}': the paper ran the Goal tasks only; {} exists in the "
          "'standard' (Safety-Gymnasium) variant",
          task.name, VariantName(variant), task.name);
  NavigationTaskSpec spec;
  spec.name = task.name;
  spec.family = task.family;
  spec.robot = task.robot;
  spec.level = task.level;
  spec.variant = variant;
  switch (task.family) {
    case TaskFamily::kGoal: FillGoal(spec); break;
    case TaskFamily::kButton: FillButton(spec); break;
    case TaskFamily::kPush: FillPush(spec); break;
    case TaskFamily::kCircle: FillCircle(spec); break;
  }
  return spec;
}

std::vector<LidarObject> LidarObjects(const NavigationTaskSpec& spec) {
  std::vector<LidarObject> objects;
  const auto add = [&objects](bool present, LidarObject object) {
    if (present) objects.push_back(object);
  };
  switch (spec.family) {
    case TaskFamily::kGoal:
      add(true, LidarObject::kGoal);
      add(spec.num_hazards > 0, LidarObject::kHazards);
      add(spec.num_vases > 0, LidarObject::kVases);
      break;
    case TaskFamily::kButton:
      add(true, LidarObject::kButtons);
      add(true, LidarObject::kGoal);
      add(spec.num_hazards > 0, LidarObject::kHazards);
      add(spec.num_gremlins > 0, LidarObject::kGremlins);
      break;
    case TaskFamily::kPush:
      add(true, LidarObject::kGoal);
      add(spec.num_hazards > 0, LidarObject::kHazards);
      add(spec.num_pillars > 0, LidarObject::kPillars);
      add(true, LidarObject::kPushBox);
      break;
    case TaskFamily::kCircle:
      add(true, LidarObject::kCircle);
      break;
  }
  return objects;
}

std::string LidarKey(LidarObject object) {
  switch (object) {
    case LidarObject::kGoal: return "goal_lidar";
    case LidarObject::kHazards: return "hazards_lidar";
    case LidarObject::kVases: return "vases_lidar";
    case LidarObject::kButtons: return "buttons_lidar";
    case LidarObject::kGremlins: return "gremlins_lidar";
    case LidarObject::kPillars: return "pillars_lidar";
    case LidarObject::kPushBox: return "push_box_lidar";
    case LidarObject::kCircle: return "circle_lidar";
  }
  return "";
}

int ObservationSize(const NavigationTaskSpec& spec) {
  if (spec.observation == ObservationKind::kEgoState) {
    return 8 + 2 * (spec.num_vases + spec.num_hazards);
  }
  // accelerometer, gyro, magnetometer, velocimeter; the stock car's ball joint (3 + 9; the
  // paper's rover has no joint sensors); lidars.
  const bool stock_car = spec.robot == RobotKind::kCar && !IsPaperWorld(spec.variant);
  const int sensors = 12 + (stock_car ? 12 : 0);
  return sensors + static_cast<int>(LidarObjects(spec).size()) * spec.lidar_bins;
}

NavigationTaskSpec NavigationTaskSpecByName(const std::string& task, Variant variant) {
  return MakeNavigationTaskSpec(FindTask(task), variant);
}

}  // namespace cmbrl

// The numbers of one Safety Gym Goal task in one variant (facts A1 to A6, B0, B1).
#pragma once

#include <string>
#include <vector>

#include "cmbrl/env/scene.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/env/variant.h"

namespace cmbrl {

enum class ObservationKind {
  // Stock (Safety-Gymnasium, facts A5): the robot's sensors in its order (accelerometer,
  // velocimeter, gyro, magnetometer), its joint sensors, then the 16-bin pseudo-lidars in the
  // order the task adds its objects (goal, hazards, vases).
  kLidar,
  // The original Safety Gym's: the same blocks in alphabetical order of their keys (the paper's
  // lidar variant, whose original logs came from it).
  kLidarSorted,
  kEgoState,  // paper: velocities, heading and ego-frame XY of goal, vases and hazards
};

// Whether the observation is sensors and pseudo-lidars (in either order).
inline bool IsLidarObservation(ObservationKind kind) { return kind != ObservationKind::kEgoState; }

// Every number of a Goal task; MakeGoalTaskSpec fills it for a task and variant.
struct GoalTaskSpec {
  std::string name;  // "PointGoal1", ...
  RobotKind robot = RobotKind::kPoint;
  int level = 1;
  Variant variant = Variant::kPaper;

  // Layout (A1, B0).
  int num_hazards = 0;
  int num_vases = 0;
  bool vases_constrained = false;
  Extents placement;              // objects are drawn in here, shrunk by their own keep-out (m)
  double robot_keepout = 0.4;     // m
  double goal_keepout = 0.305;    // m; 0.35 in the paper's suite
  double hazard_keepout = 0.18;   // m
  double vase_keepout = 0.15;     // m
  double placement_margin = 0.0;  // extra gap between keep-outs (m)
  int placement_tries = 100;      // draws per object before the layout restarts
  int layout_tries = 10000;       // layouts before giving up
  int goal_tries = 10000;         // draws when the goal alone is re-sampled

  // Objects (A1).
  double goal_size = 0.3;       // goal radius; reached within this XY distance (m)
  double hazard_size = 0.2;     // hazard radius (m)
  double vase_half_size = 0.1;  // vase box half-size (m)
  double vase_sink = 4e-5;      // vases start this far into the floor (m)
  double vase_density = 0.001;  // kg/m^3

  // Reward (A2) and cost (A3, B0).
  double reward_distance = 1.0;           // per metre of progress towards the goal
  double reward_goal = 1.0;               // bonus when the goal is reached
  double reward_clip = 10.0;              // safety net on the progress term
  double reward_physics_error = -10.0;    // reward of a step whose physics blew up
  double hazard_cost = 1.0;               // per metre inside a hazard
  double vase_contact_cost = 1.0;         // per robot-vase contact
  double vase_velocity_cost = 1.0;        // per m/s of vase speed
  double vase_velocity_threshold = 1e-4;  // m/s; 1e-3 in the paper's suite

  // Timing (A4, B0): one agent step runs action_repeat env steps of frame_skip physics steps.
  int frame_skip = 10;
  int action_repeat = 1;     // 3 (Point) / 2 (Car) in the paper's wrapper
  int max_env_steps = 1000;  // episode length in env steps: 300 (Point) / 150 (Car) in paper

  // Observation (A5, B1).
  ObservationKind observation = ObservationKind::kLidar;
  int lidar_bins = 16;
  double lidar_max_dist = 3.0;  // m
};

// The spec of a task (task_list.h) in a variant. Throws cmbrl::Error for a level other than 1
// or 2.
GoalTaskSpec MakeGoalTaskSpec(const TaskEntry& task, Variant variant);

// Size of the observation vector: the ego-state's 8 + 2 per vase and hazard (facts B1), or the
// lidar observation's sensors and bins (facts A5).
int ObservationSize(const GoalTaskSpec& spec);

// The spec of a named task; throws cmbrl::Error naming the task and the valid ones otherwise.
GoalTaskSpec GoalTaskSpecByName(const std::string& task, Variant variant);

}  // namespace cmbrl

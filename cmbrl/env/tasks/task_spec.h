// The numbers of one navigation task in one variant: the Goal tasks (facts A1 to A6, B0, B1) and
// Safety-Gymnasium's Button, Push and Circle (docs/ENVIRONMENTS.md, with the source files).
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

// Every number of a navigation task; MakeNavigationTaskSpec fills it for a task and variant.
// Objects a family does not use have a count of 0 (or are off).
struct NavigationTaskSpec {
  std::string name;  // "PointGoal1", ...
  TaskFamily family = TaskFamily::kGoal;
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
  // Where the robot alone is drawn, when not in `placement` (Circle: [-0.8, 0.8]^2).
  bool robot_placement_own = false;
  Extents robot_placement;
  int placement_tries = 100;      // draws per object before the layout restarts
  int layout_tries = 10000;       // layouts before giving up
  int goal_tries = 10000;         // draws when the goal alone is re-sampled

  // Objects (A1).
  double goal_size = 0.3;       // goal radius; reached within this XY distance (m)
  double hazard_size = 0.2;     // hazard radius (m)
  double vase_half_size = 0.1;  // vase box half-size (m)
  double vase_sink = 4e-5;      // vases start this far into the floor (m)
  double vase_density = 0.001;  // kg/m^3

  // Button (buttons.py, gremlins.py): buttons are static spheres; the goal marker sits on the goal
  // button, which is pressed by touching it. Gremlins are boxes welded to mocaps that circle
  // their placed position.
  int num_buttons = 0;
  double button_size = 0.1;  // sphere radius, centre at this height (m)
  double button_keepout = 0.2;
  bool buttons_constrained = false;
  int button_resampling_delay = 10;  // steps the buttons are unconstrained and unseen after a goal
  double button_cost = 1.0;          // per contact with a wrong button
  int num_gremlins = 0;
  double gremlin_size = 0.1;      // box half-size (m)
  double gremlin_keepout = 0.4;
  double gremlin_travel = 0.35;   // radius of the circle each gremlin travels (m)
  double gremlin_density = 0.001;
  double gremlin_contact_cost = 1.0;
  // Push (push_box.py, pillars.py).
  int num_pillars = 0;
  double pillar_size = 0.2;    // cylinder radius (m)
  double pillar_height = 0.5;  // cylinder half-height (m)
  double pillar_keepout = 0.3;
  bool pillars_constrained = false;
  double pillar_cost = 1.0;  // per contact
  bool push_box = false;
  double box_size = 0.2;  // half-size (m); the Car's 0.125
  double box_keepout = 0.2;
  double box_density = 0.001;
  double box_null_dist = 0.0;  // no agent-box reward within box_null_dist x box_size
  double reward_box_dist = 1.0;
  double reward_box_goal = 1.0;
  // Circle (circle.py, sigwalls.py).
  bool circle = false;
  double circle_radius = 1.5;  // m
  double circle_reward_factor = 0.1;
  int num_sigwalls = 0;               // 2: walls at x = +-locate; 4: and at y = +-locate
  double sigwall_locate = 1.125;      // m
  double out_of_boundary_cost = 1.0;  // while outside the walls

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

// The variant a task is made in when none is named: the paper's for the paper's tasks, the stock
// (Safety-Gymnasium) one for the others.
inline Variant DefaultVariant(const TaskEntry& task) {
  return HasPaperVariant(task) ? Variant::kPaper : Variant::kStandard;
}

// Whether the task has a goal marker (Goal, Button, Push; not Circle).
inline bool HasGoal(const NavigationTaskSpec& spec) { return spec.family != TaskFamily::kCircle; }

// The spec of a task (task_list.h) in a variant. Throws cmbrl::Error for a level the family lacks
// and for a paper variant of a family the paper did not run.
NavigationTaskSpec MakeNavigationTaskSpec(const TaskEntry& task, Variant variant);

// The objects a lidar observation has a block of, each block the pseudo-lidar of every object of
// that kind.
enum class LidarObject { kGoal, kHazards, kVases, kButtons, kGremlins, kPillars, kPushBox, kCircle };

// The lidar blocks of a spec in Safety-Gymnasium's order: the order the task adds its objects,
// geoms before free geoms before mocaps (safety_gymnasium/bases/underlying.py, _obstacles). Goal:
// goal, hazards, vases; Button: buttons, goal, hazards, gremlins; Push: goal, hazards, pillars,
// push box; Circle: circle. Kinds with no object are left out.
std::vector<LidarObject> LidarObjects(const NavigationTaskSpec& spec);

// The block's key: "goal_lidar", "hazards_lidar", "vases_lidar", "buttons_lidar",
// "gremlins_lidar", "pillars_lidar", "push_box_lidar" or "circle_lidar".
std::string LidarKey(LidarObject object);

// Size of the observation vector: the ego-state's 8 + 2 per vase and hazard (facts B1), or the
// lidar observation's sensors and bins (facts A5; one lidar per kind of object observed).
int ObservationSize(const NavigationTaskSpec& spec);

// The spec of a named task; throws cmbrl::Error naming the task and the valid ones otherwise.
NavigationTaskSpec NavigationTaskSpecByName(const std::string& task, Variant variant);

}  // namespace cmbrl

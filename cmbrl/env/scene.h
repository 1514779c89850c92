// Ground truth of a navigation arena, for pictures and tests: never part of what an agent observes.
// Environments that have such a scene offer it through Env::scene_source().
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/vec2.h"

namespace cmbrl {

// A planar pose: position on the floor and heading (rad, counter-clockwise from world +x).
struct Pose2 {
  Vec2 position;
  double yaw = 0.0;
};

// Axis-aligned rectangle on the floor.
struct Extents {
  double x_min = 0.0, y_min = 0.0, x_max = 0.0, y_max = 0.0;
};

// The arena at one moment.
struct SceneState {
  std::string robot_name;     // "point", "car" (stock two-wheel) or "rover"
  double robot_radius = 0.0;  // radius of a disc that covers the robot's footprint (m)
  Pose2 robot;
  // Cosine of the robot's tilt: the world z component of its body z axis. 1 upright, 0 on its
  // side, -1 upside down. A planar robot (Point) is always 1.
  double robot_upright = 1.0;
  Vec2 goal;
  std::vector<Vec2> hazards;
  std::vector<Pose2> vases;  // live positions: vases can be pushed
  bool has_goal = true;  // Circle has none
  double goal_radius = 0.0;
  double hazard_radius = 0.0;
  double vase_half_size = 0.0;
  Extents placement;  // where layouts are sampled
  // Button: the buttons, which one is the goal, and whether pressing another costs now.
  std::vector<Vec2> buttons;
  int goal_button = -1;
  bool buttons_active = false;
  double button_radius = 0.0;
  std::vector<Pose2> gremlins;  // live
  double gremlin_half_size = 0.0;
  // Push: the pillars and the box (live).
  std::vector<Vec2> pillars;
  double pillar_radius = 0.0;
  std::optional<Pose2> box;
  double box_half_size = 0.0;
  // Circle: the ring's radius (0: none) and the walls at +-wall_locate (x for 2, x and y for 4).
  double circle_radius = 0.0;
  double wall_locate = 0.0;
  int num_walls = 0;
};

// Thread-compatible.
class SceneSource {
 public:
  virtual ~SceneSource() = default;
  virtual SceneState Scene() const = 0;
};

}  // namespace cmbrl

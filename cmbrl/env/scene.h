// Ground truth of a Goal arena, for pictures and tests: never part of what an agent observes.
// Environments that have such a scene offer it through Env::scene_source().
#pragma once

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
  double goal_radius = 0.0;
  double hazard_radius = 0.0;
  double vase_half_size = 0.0;
  Extents placement;  // where layouts are sampled
};

// Thread-compatible.
class SceneSource {
 public:
  virtual ~SceneSource() = default;
  virtual SceneState Scene() const = 0;
};

}  // namespace cmbrl

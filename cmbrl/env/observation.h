// Observation pieces of the Goal tasks: ego-frame coordinates and Safety Gym's pseudo-lidar
// (facts A5, B1). Pure functions of positions, so they are tested against hand-computed values.
#pragma once

#include <array>
#include <vector>

#include "cmbrl/core/vec2.h"

namespace cmbrl {

// Robot frame: body origin in world coordinates and its rotation matrix, row-major as MuJoCo's
// xmat (columns are the body axes in world coordinates).
struct RobotFrame {
  std::array<double, 3> position{};
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
};

// XY of a floor point (z = 0) in the robot's frame: R^T (p - robot_position), first two
// components. +x is the robot's heading, +y its left.
Vec2 EgoXY(const RobotFrame& robot, Vec2 point);

// Safety Gym's "pseudo" lidar with aliasing: `bins` bins covering [0, 2 pi) counter-clockwise
// from the robot's +x; each object reads max(0, max_dist - d) / max_dist in the bin of its ego
// angle, the bin keeping the largest reading; the next bin gets alias * reading and the previous
// (1 - alias) * reading (each kept as a max), alias being the object's fractional position in
// its bin. Writes `bins` values to `out`.
void PseudoLidar(const RobotFrame& robot, const std::vector<Vec2>& objects, int bins,
                 double max_dist, double* out);

}  // namespace cmbrl

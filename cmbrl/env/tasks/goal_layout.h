// Random layouts of the Goal arena with keep-outs and rejection (facts A1).
#pragma once

#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/scene.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

// Where everything starts: robot pose, goal, hazards and vases (with their yaw).
struct GoalLayout {
  Pose2 robot;
  Vec2 goal;
  std::vector<Vec2> hazards;  // (num_hazards)
  std::vector<Pose2> vases;   // (num_vases)
};

// Draws a layout as Safety Gym does: objects in the order robot, goal, hazards, vases, each
// uniform in the placement extents shrunk by its own keep-out, rejected while closer to a placed
// object than the sum of both keep-outs plus the margin; placement_tries per object, then the
// whole layout restarts, up to layout_tries layouts (then throws cmbrl::Error). Rotations are
// drawn afterwards in the order robot, vases, goal, hazards.
GoalLayout SampleGoalLayout(const GoalTaskSpec& spec, Rng& rng);

// Re-draws only the goal against the other objects where they are now, up to goal_tries times.
// Returns false, leaving the goal unchanged, when no draw fits.
bool ResampleGoal(const GoalTaskSpec& spec, GoalLayout& layout, Rng& rng);

}  // namespace cmbrl

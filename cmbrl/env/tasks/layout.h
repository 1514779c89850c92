// Random layouts of a navigation arena with keep-outs and rejection (facts A1; Safety-Gymnasium's
// draw_placement for every family).
#pragma once

#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/scene.h"
#include "cmbrl/env/tasks/task_spec.h"

namespace cmbrl {

// Where everything starts: robot pose, goal, and each family's objects (with their yaw where it
// matters). A family's missing objects are empty.
struct NavigationLayout {
  Pose2 robot;
  Vec2 goal;                   // Circle: unused
  std::vector<Vec2> hazards;   // (num_hazards)
  std::vector<Pose2> vases;    // (num_vases)
  std::vector<Vec2> buttons;   // (num_buttons)
  std::vector<Pose2> gremlins; // (num_gremlins): the centres they circle
  std::vector<Vec2> pillars;   // (num_pillars)
  Pose2 box;                   // the push box, when the spec has one
};

// Draws a layout as Safety Gym does: the robot, then the objects in the order the task adds them
// (Goal: goal, hazards, vases; Button: buttons, goal, hazards, gremlins; Push: goal, hazards,
// pillars, box; Circle: none), each uniform in the placement extents shrunk by its own keep-out,
// rejected while closer to a placed object than the sum of both keep-outs plus the margin;
// placement_tries per object, then the whole layout restarts, up to layout_tries layouts (then
// throws cmbrl::Error). Rotations are drawn afterwards: the Goal tasks' in the order robot, vases,
// goal, hazards; the others' robot, then the box and gremlins.
NavigationLayout SampleLayout(const NavigationTaskSpec& spec, Rng& rng);

// Re-draws only the goal against the other objects (every one but the goal) where they are now, up to goal_tries times.
// Returns false, leaving the goal unchanged, when no draw fits.
bool ResampleGoal(const NavigationTaskSpec& spec, NavigationLayout& layout, Rng& rng);

}  // namespace cmbrl

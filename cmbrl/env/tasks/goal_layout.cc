#include "cmbrl/env/tasks/goal_layout.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

// An object already placed, with the keep-out radius it claims.
struct Placed {
  Vec2 position;
  double keepout;
};

Vec2 DrawInExtents(const Extents& extents, double keepout, Rng& rng) {
  // x first, then y, as Safety Gym's draw_placement.
  const double x = Uniform(rng, extents.x_min + keepout, extents.x_max - keepout);
  const double y = Uniform(rng, extents.y_min + keepout, extents.y_max - keepout);
  return {x, y};
}

bool Fits(Vec2 candidate, double keepout, double margin, const std::vector<Placed>& placed) {
  for (const Placed& other : placed) {
    if (Distance(candidate, other.position) < keepout + other.keepout + margin) return false;
  }
  return true;
}

// Places one object with up to `tries` draws; false when none fits.
bool PlaceObject(const GoalTaskSpec& spec, double keepout, int tries, Rng& rng,
                 std::vector<Placed>& placed, Vec2& position) {
  for (int attempt = 0; attempt < tries; ++attempt) {
    const Vec2 candidate = DrawInExtents(spec.placement, keepout, rng);
    if (Fits(candidate, keepout, spec.placement_margin, placed)) {
      placed.push_back({candidate, keepout});
      position = candidate;
      return true;
    }
  }
  return false;
}

// One attempt at a whole layout; false when an object ran out of tries.
bool TrySampleLayout(const GoalTaskSpec& spec, Rng& rng, GoalLayout& layout) {
  std::vector<Placed> placed;
  placed.reserve(2 + spec.num_hazards + spec.num_vases);
  layout.hazards.assign(spec.num_hazards, Vec2{});
  layout.vases.assign(spec.num_vases, Pose2{});
  const int tries = spec.placement_tries;
  if (!PlaceObject(spec, spec.robot_keepout, tries, rng, placed, layout.robot.position)) {
    return false;
  }
  if (!PlaceObject(spec, spec.goal_keepout, tries, rng, placed, layout.goal)) return false;
  for (Vec2& hazard : layout.hazards) {
    if (!PlaceObject(spec, spec.hazard_keepout, tries, rng, placed, hazard)) return false;
  }
  for (Pose2& vase : layout.vases) {
    if (!PlaceObject(spec, spec.vase_keepout, tries, rng, placed, vase.position)) return false;
  }
  return true;
}

}  // namespace

GoalLayout SampleGoalLayout(const GoalTaskSpec& spec, Rng& rng) {
  GoalLayout layout;
  bool found = false;
  for (int attempt = 0; attempt < spec.layout_tries && !found; ++attempt) {
    found = TrySampleLayout(spec, rng, layout);
  }
  Require(found, "no layout of {} fits its keep-outs after {} tries", spec.name, spec.layout_tries);
  // Rotations in Safety Gym's order. The goal's and hazards' rotations are drawn and discarded:
  // their cylinders are symmetric, but the draws keep the generator's sequence in that order.
  layout.robot.yaw = Uniform(rng, 0.0, kTwoPi);
  for (Pose2& vase : layout.vases) vase.yaw = Uniform(rng, 0.0, kTwoPi);
  for (int i = 0; i < 1 + spec.num_hazards; ++i) Uniform(rng, 0.0, kTwoPi);
  return layout;
}

bool ResampleGoal(const GoalTaskSpec& spec, GoalLayout& layout, Rng& rng) {
  std::vector<Placed> others;
  others.reserve(1 + layout.hazards.size() + layout.vases.size());
  others.push_back({layout.robot.position, spec.robot_keepout});
  for (const Vec2& hazard : layout.hazards) others.push_back({hazard, spec.hazard_keepout});
  for (const Pose2& vase : layout.vases) others.push_back({vase.position, spec.vase_keepout});
  Vec2 goal;
  if (!PlaceObject(spec, spec.goal_keepout, spec.goal_tries, rng, others, goal)) return false;
  layout.goal = goal;
  return true;
}

}  // namespace cmbrl

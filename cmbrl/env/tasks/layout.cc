#include "cmbrl/env/tasks/layout.h"

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

// Places one object with up to `tries` draws in `extents`; false when none fits.
bool PlaceObjectIn(const NavigationTaskSpec& spec, const Extents& extents, double keepout,
                   int tries, Rng& rng, std::vector<Placed>& placed, Vec2& position) {
  for (int attempt = 0; attempt < tries; ++attempt) {
    const Vec2 candidate = DrawInExtents(extents, keepout, rng);
    if (Fits(candidate, keepout, spec.placement_margin, placed)) {
      placed.push_back({candidate, keepout});
      position = candidate;
      return true;
    }
  }
  return false;
}

bool PlaceObject(const NavigationTaskSpec& spec, double keepout, int tries, Rng& rng,
                 std::vector<Placed>& placed, Vec2& position) {
  return PlaceObjectIn(spec, spec.placement, keepout, tries, rng, placed, position);
}

Vec2& PositionOf(Vec2& point) { return point; }
Vec2& PositionOf(Pose2& pose) { return pose.position; }

// Places every object of `objects` (points or poses) with `keepout`; false when one ran out of
// tries.
template <typename Object>
bool PlaceAll(const NavigationTaskSpec& spec, double keepout, Rng& rng,
              std::vector<Placed>& placed, std::vector<Object>& objects) {
  for (Object& object : objects) {
    if (!PlaceObject(spec, keepout, spec.placement_tries, rng, placed, PositionOf(object))) {
      return false;
    }
  }
  return true;
}

// One attempt at a whole layout; false when an object ran out of tries.
bool TrySampleLayout(const NavigationTaskSpec& spec, Rng& rng, NavigationLayout& layout) {
  std::vector<Placed> placed;
  placed.reserve(3 + spec.num_hazards + spec.num_vases + spec.num_buttons + spec.num_gremlins +
                 spec.num_pillars);
  layout.hazards.assign(spec.num_hazards, Vec2{});
  layout.vases.assign(spec.num_vases, Pose2{});
  layout.buttons.assign(spec.num_buttons, Vec2{});
  layout.gremlins.assign(spec.num_gremlins, Pose2{});
  layout.pillars.assign(spec.num_pillars, Vec2{});
  const int tries = spec.placement_tries;
  const Extents& robot_extents = spec.robot_placement_own ? spec.robot_placement : spec.placement;
  if (!PlaceObjectIn(spec, robot_extents, spec.robot_keepout, tries, rng, placed,
                     layout.robot.position)) {
    return false;
  }
  const auto place_goal = [&] {
    return PlaceObject(spec, spec.goal_keepout, tries, rng, placed, layout.goal);
  };
  switch (spec.family) {
    case TaskFamily::kGoal:
      return place_goal() && PlaceAll(spec, spec.hazard_keepout, rng, placed, layout.hazards) &&
             PlaceAll(spec, spec.vase_keepout, rng, placed, layout.vases);
    case TaskFamily::kButton:
      return PlaceAll(spec, spec.button_keepout, rng, placed, layout.buttons) && place_goal() &&
             PlaceAll(spec, spec.hazard_keepout, rng, placed, layout.hazards) &&
             PlaceAll(spec, spec.gremlin_keepout, rng, placed, layout.gremlins);
    case TaskFamily::kPush:
      return place_goal() && PlaceAll(spec, spec.hazard_keepout, rng, placed, layout.hazards) &&
             PlaceAll(spec, spec.pillar_keepout, rng, placed, layout.pillars) &&
             PlaceObject(spec, spec.box_keepout, tries, rng, placed, layout.box.position);
    case TaskFamily::kCircle:
      return true;
  }
  return false;
}

}  // namespace

NavigationLayout SampleLayout(const NavigationTaskSpec& spec, Rng& rng) {
  NavigationLayout layout;
  bool found = false;
  for (int attempt = 0; attempt < spec.layout_tries && !found; ++attempt) {
    found = TrySampleLayout(spec, rng, layout);
  }
  Require(found, "no layout of {} fits its keep-outs after {} tries", spec.name, spec.layout_tries);
  // Rotations in Safety Gym's order. The goal's and hazards' rotations are drawn and discarded:
  // their cylinders are symmetric, but the draws keep the generator's sequence in that order.
  layout.robot.yaw = Uniform(rng, 0.0, kTwoPi);
  if (spec.family == TaskFamily::kGoal) {
    for (Pose2& vase : layout.vases) vase.yaw = Uniform(rng, 0.0, kTwoPi);
    for (int i = 0; i < 1 + spec.num_hazards; ++i) Uniform(rng, 0.0, kTwoPi);
    return layout;
  }
  if (spec.push_box) layout.box.yaw = Uniform(rng, 0.0, kTwoPi);
  for (Pose2& gremlin : layout.gremlins) gremlin.yaw = Uniform(rng, 0.0, kTwoPi);
  return layout;
}

bool ResampleGoal(const NavigationTaskSpec& spec, NavigationLayout& layout, Rng& rng) {
  std::vector<Placed> others;
  others.push_back({layout.robot.position, spec.robot_keepout});
  for (const Vec2& hazard : layout.hazards) others.push_back({hazard, spec.hazard_keepout});
  for (const Pose2& vase : layout.vases) others.push_back({vase.position, spec.vase_keepout});
  for (const Vec2& button : layout.buttons) others.push_back({button, spec.button_keepout});
  for (const Pose2& gremlin : layout.gremlins) {
    others.push_back({gremlin.position, spec.gremlin_keepout});
  }
  for (const Vec2& pillar : layout.pillars) others.push_back({pillar, spec.pillar_keepout});
  if (spec.push_box) others.push_back({layout.box.position, spec.box_keepout});
  Vec2 goal;
  if (!PlaceObject(spec, spec.goal_keepout, spec.goal_tries, rng, others, goal)) return false;
  layout.goal = goal;
  return true;
}

}  // namespace cmbrl

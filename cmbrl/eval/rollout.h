// Running whole episodes of a policy in an environment, with the record pictures need.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <variant>
#include <vector>

#include "cmbrl/agent/policy.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/scene.h"

namespace cmbrl {

// What one episode did.
struct EpisodeRecord {
  double episode_return = 0.0;  // sum of rewards
  double episode_cost = 0.0;    // number of agent steps with a violation
  int steps = 0;                // agent steps
  int env_steps = 0;            // inner env steps (action repeat)
  int goals_met = 0;
  int hazard_steps = 0;  // agent steps that ended with the robot inside a hazard
  int vase_steps = 0;    // agent steps with a vase cost (contact or vase speed)
  // Metres from the robot, after each step, to the goal it pursued in that step: their mean, and
  // the steps that ended within kNearGoalMetres of it (where the robot is about to score).
  double mean_goal_distance = 0.0;
  int steps_near_goal = 0;
  bool terminated = false;
  bool truncated = false;
  std::vector<Vec2> path;             // robot position before the first step and after each
  std::vector<bool> path_violations;  // (path.size()): cost of the step that reached it
  std::vector<Vec2> reached_goals;    // goal positions at the moments they were reached
  SceneState final_scene;
  // The environment's own pictures (Env::Frame), where asked for: after the reset, every
  // `frame_every` steps and at the end.
  std::vector<RgbFrame> frames;
};

// What "near the goal" means in EpisodeRecord::steps_near_goal: about three goal radii (0.3 m in
// every Goal task), the distance a planning horizon closes in a few steps.
inline constexpr double kNearGoalMetres = 1.0;

// Called after the policy chose the action of step `step` and before the environment runs it,
// with the scene the action was chosen in.
using AfterActHook = std::function<void(int step, const SceneState& scene)>;

// Resets the environment (with `seed`, or continuing its generator) and runs the policy until the
// episode terminates or is truncated. For an environment without a scene (Env::scene_source:
// a declared or Python task) the path and the goal figures stay empty and zero, and the hook
// gets an empty scene.
// `frame_every` > 0 keeps the environment's own pictures in EpisodeRecord::frames (none where it
// draws none).
EpisodeRecord RunEpisode(Env& env, Policy& policy, std::optional<std::uint64_t> seed,
                         const AfterActHook& after_act = {}, int frame_every = 0);

// An episode's counts in the navigation world, by the names `cmbrl eval` and cmbrl.evaluate give
// them (goals_met, hazard_steps, vase_steps, mean_goal_distance, steps_near_goal); none for an
// environment without a scene, which has no goals, hazards or vases to count.
struct NamedFigure {
  const char* name;
  std::variant<std::int64_t, double> value;  // a count, or a mean
};
std::vector<NamedFigure> NavigationFigures(const EpisodeRecord& record);

}  // namespace cmbrl

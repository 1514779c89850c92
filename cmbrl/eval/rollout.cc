#include "cmbrl/eval/rollout.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

EpisodeRecord RunEpisode(Env& env, Policy& policy, std::optional<std::uint64_t> seed,
                         const AfterActHook& after_act, int frame_every) {
  // An environment without a scene (a declared or Python task) records sums and counts only.
  const SceneSource* scenes = env.scene_source();
  EpisodeRecord record;
  std::vector<double> observation = env.Reset(seed);
  policy.BeginEpisode();
  SceneState scene = scenes != nullptr ? scenes->Scene() : SceneState();
  double goal_distance_sum = 0.0;
  const auto take_frame = [&] {
    if (std::optional<RgbFrame> frame = env.Frame()) record.frames.push_back(std::move(*frame));
  };
  if (frame_every > 0) take_frame();
  if (scenes != nullptr) {
    record.path.push_back(scene.robot.position);
    record.path_violations.push_back(false);
  }
  for (;;) {
    const Vec2 goal_before = scene.goal;
    const std::vector<double> action = policy.Act(observation);
    if (after_act) after_act(record.steps, scene);
    StepResult step = env.Step(action);
    if (scenes != nullptr) scene = scenes->Scene();
    record.episode_return += step.reward;
    record.episode_cost += step.cost;
    ++record.steps;
    record.env_steps += step.info.env_steps;
    if (step.info.goal_met) {
      ++record.goals_met;
      record.reached_goals.push_back(goal_before);
    }
    if (step.info.cost_hazards > 0.0) ++record.hazard_steps;
    if (step.info.cost_vases_contact > 0.0 || step.info.cost_vases_velocity > 0.0) {
      ++record.vase_steps;
    }
    if (scenes != nullptr) {
      const double distance = std::hypot(scene.robot.position.x - goal_before.x,
                                         scene.robot.position.y - goal_before.y);
      goal_distance_sum += distance;
      if (distance <= kNearGoalMetres) ++record.steps_near_goal;
      record.path.push_back(scene.robot.position);
      record.path_violations.push_back(step.cost > 0.0);
    }
    observation = std::move(step.observation);
    const bool end = step.terminated || step.truncated;
    if (frame_every > 0 && (end || record.steps % frame_every == 0)) take_frame();
    if (end) {
      record.terminated = step.terminated;
      record.truncated = step.truncated;
      break;
    }
  }
  record.mean_goal_distance = goal_distance_sum / record.steps;
  record.final_scene = std::move(scene);
  return record;
}

std::vector<NamedFigure> NavigationFigures(const EpisodeRecord& record) {
  if (record.path.empty()) return {};  // no scene
  return {{"goals_met", std::int64_t{record.goals_met}},
          {"hazard_steps", std::int64_t{record.hazard_steps}},
          {"vase_steps", std::int64_t{record.vase_steps}},
          {"mean_goal_distance", record.mean_goal_distance},
          {"steps_near_goal", std::int64_t{record.steps_near_goal}}};
}

}  // namespace cmbrl

#include "cmbrl/eval/evaluation.h"

#include <fmt/format.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cmath>

#include "cmbrl/learners/mpc/mpc_agent.h"
#include "cmbrl/core/check.h"
#include "cmbrl/config/config.h"
#include "cmbrl/eval/loaded_run.h"
#include "cmbrl/run/run_directory.h"
#include "cmbrl/viz/frame_strip.h"

namespace cmbrl {
namespace {

std::optional<std::uint64_t> EpisodeResetSeed(const EvaluationOptions& options, int episode) {
  if (options.reseed_each_episode) return options.seed + static_cast<std::uint64_t>(episode);
  return episode == 0 ? std::optional<std::uint64_t>(options.seed) : std::nullopt;
}

// Predicted robot positions in the world: the predicted magnetometer gives the heading theta
// ((-0.5 sin theta, -0.5 cos theta) in the body frame), the predicted ego-frame goal the offset,
// and the goal itself does not move: p = goal - R(theta) goal_ego.
// Every path of the objective's last evaluation, sample-major (n * E + e).
std::vector<PredictedPath> WorldPaths(MpcAgent& agent, const BoxSpec& spec, Vec2 goal,
                                      Vec2 robot) {
  const torch::Tensor trajectories = agent.objective()
                                         .last_trajectories()
                                         .to(torch::kCPU, torch::kFloat)
                                         .contiguous();  // (E,N,H,S)
  const torch::Tensor constraint =
      agent.objective().last_values().constraint_cost.to(torch::kCPU, torch::kFloat).contiguous();
  const int mx = spec.IndexOf("magnetometer_x"), my = spec.IndexOf("magnetometer_y");
  const int gx = spec.IndexOf("goal_x"), gy = spec.IndexOf("goal_y");
  const std::int64_t samples = trajectories.size(1), horizon = trajectories.size(2);
  const auto states = trajectories.accessor<float, 4>();
  const auto costs = constraint.accessor<float, 1>();  // (N)
  const auto point = [&](std::int64_t e, std::int64_t n, std::int64_t t) {
    const double theta = std::atan2(-states[e][n][t][mx], -states[e][n][t][my]);
    const double ex = states[e][n][t][gx], ey = states[e][n][t][gy];
    return Vec2{goal.x - (std::cos(theta) * ex - std::sin(theta) * ey),
                goal.y - (std::sin(theta) * ex + std::cos(theta) * ey)};
  };
  std::vector<PredictedPath> paths;
  paths.reserve(static_cast<size_t>(samples * trajectories.size(0)));
  for (std::int64_t n = 0; n < samples; ++n) {
    for (std::int64_t e = 0; e < trajectories.size(0); ++e) {
      PredictedPath path;
      path.feasible = costs[n] == 0.0f;
      path.points.push_back(robot);
      for (std::int64_t t = 0; t < horizon; ++t) path.points.push_back(point(e, n, t));
      paths.push_back(std::move(path));
    }
  }
  return paths;
}

}  // namespace

PlanPaths TakePlanPaths(MpcAgent& agent, const BoxSpec& spec, const SceneState& scene) {
  PlanPaths paths;
  paths.members = static_cast<int>(agent.objective().last_trajectories().size(0));
  paths.population = WorldPaths(agent, spec, scene.goal, scene.robot.position);
  // The executed plan: its final mean rolled through the objective once more.
  agent.objective().Evaluate(agent.last_result().sequence.unsqueeze(0));
  paths.chosen = WorldPaths(agent, spec, scene.goal, scene.robot.position);
  for (PredictedPath& chosen : paths.chosen) chosen.chosen = true;
  return paths;
}

std::vector<PredictedPath> SelectPredictions(const PlanPaths& paths, int samples) {
  Require(samples >= 1, "samples is {}: expected at least 1", samples);
  const size_t members = static_cast<size_t>(std::max(1, paths.members));
  const size_t population = paths.population.size() / members;
  const size_t keep = std::min(population, static_cast<size_t>(samples));
  std::vector<PredictedPath> selected;
  selected.reserve((keep + 1) * members);
  for (size_t k = 0; k < keep; ++k) {
    const size_t n = k * population / keep;  // evenly spread, the first sample included
    selected.insert(selected.end(), paths.population.begin() + static_cast<std::ptrdiff_t>(n * members),
                    paths.population.begin() + static_cast<std::ptrdiff_t>((n + 1) * members));
  }
  selected.insert(selected.end(), paths.chosen.begin(), paths.chosen.end());
  return selected;
}

std::vector<PredictedPath> PlannerPredictions(MpcAgent& agent, const BoxSpec& spec,
                                              const SceneState& scene, int samples) {
  return SelectPredictions(TakePlanPaths(agent, spec, scene), samples);
}

std::vector<EvaluatedEpisode> EvaluateRun(const std::string& run_dir,
                                          const EvaluationOptions& options,
                                          const LearnerInputs& inputs) {
  Require(options.episodes >= 1, "episodes is {}: expected at least 1", options.episodes);
  // Pictures of a Python environment come from one made to draw itself, where its factory can.
  LearnerInputs given = inputs;
  if (options.frame_every > 0) {
    const RunDirectory directory(run_dir);
    if (directory.HoldsRun()) {
      given = WithDeclaredPython(LoadTrainConfig(directory.config_file().string()), given);
      if (given.python_render_env) given.python_env = given.python_render_env;
    }
  }
  LoadedRun run(run_dir, options.seed, options.overrides, given);
  Env& env = run.env();
  if (!run.is_mpc()) {
    // A model-free run: its policy's mean action, no predictions to draw.
    std::vector<EvaluatedEpisode> episodes;
    for (int k = 0; k < options.episodes; ++k) {
      EvaluatedEpisode result;
      const auto start = std::chrono::steady_clock::now();
      result.record =
          RunEpisode(env, run.policy(), EpisodeResetSeed(options, k), {}, options.frame_every);
      result.mean_ms_per_plan =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count() /
          result.record.steps;
      episodes.push_back(std::move(result));
    }
    return episodes;
  }
  MpcAgent& agent = run.mpc_agent();

  std::vector<EvaluatedEpisode> episodes;
  for (int k = 0; k < options.episodes; ++k) {
    EvaluatedEpisode result;
    double milliseconds = 0.0;
    double feasible = 0.0;
    int fallback_steps = 0;
    const auto record_plan = [&](int step, const SceneState& scene) {
      const PlanStats& plan = agent.last_plan();
      milliseconds += plan.milliseconds;
      feasible += plan.feasible_fraction;
      if (plan.infeasible_elite_fraction > 0.0) ++fallback_steps;
      if (options.predictions_every <= 0 || step % options.predictions_every != 0 ||
          env.scene_source() == nullptr) {  // paths are drawn in a scene
        return;
      }
      const std::vector<PredictedPath> paths =
          PlannerPredictions(agent, env.observation_spec(), scene, options.predicted_samples);
      result.predictions.insert(result.predictions.end(), paths.begin(), paths.end());
    };
    result.record =
        RunEpisode(env, agent, EpisodeResetSeed(options, k), record_plan, options.frame_every);
    result.mean_ms_per_plan = milliseconds / result.record.steps;
    result.mean_feasible_fraction = feasible / result.record.steps;
    result.fallback_step_fraction = static_cast<double>(fallback_steps) / result.record.steps;
    episodes.push_back(std::move(result));
  }
  return episodes;
}

namespace {

// Draws one episode, k, into `path` (WriteEpisodePictures).
void WriteEpisodePicture(const EvaluatedEpisode& episode, int k, const std::string& path) {
  const EpisodeRecord& r = episode.record;
  if (!r.path.empty()) {  // the Goal world's arena
    const ScenePicture picture{
        r.final_scene,
        r.path,
        r.path_violations,
        r.reached_goals,
        fmt::format(
            "episode {}: return {:.2f}, cost {}, goals {}{}", k, r.episode_return, r.episode_cost,
            r.goals_met,
            episode.predictions.empty() ? "" : " | plans: green feasible, red not, black chosen"),
        episode.predictions};
    WriteScenePng(picture, path);
    return;
  }
  constexpr size_t kStripFrames = 8;
  const std::vector<RgbFrame>& frames = r.frames;
  std::vector<RgbFrame> strip;
  for (size_t j = 0; j < std::min(frames.size(), kStripFrames); ++j) {
    strip.push_back(frames.size() <= kStripFrames
                        ? frames[j]
                        : frames[j * (frames.size() - 1) / (kStripFrames - 1)]);
  }
  WriteFrameStripPng(strip,
                     fmt::format("episode {}: return {:.2f}, cost {}, steps {} (frames every {} "
                                 "steps and the last)",
                                 k, r.episode_return, r.episode_cost, r.steps, kFrameEvery),
                     path);
}

}  // namespace

std::vector<std::string> WriteEpisodePictures(const std::vector<EvaluatedEpisode>& episodes,
                                              const std::string& folder) {
  for (const EvaluatedEpisode& episode : episodes) {
    Require(!episode.record.path.empty() || !episode.record.frames.empty(),
            "the run's environment draws no pictures: a Python environment draws itself where "
            "its render_mode is 'rgb_array' (its factory is called with render_mode='rgb_array' "
            "where it takes one), and a task file has no arena to draw");
  }
  std::filesystem::create_directories(folder);
  std::vector<std::string> paths;
  for (size_t k = 0; k < episodes.size(); ++k) {
    paths.push_back((std::filesystem::path(folder) / fmt::format("episode-{}.png", k)).string());
    WriteEpisodePicture(episodes[k], static_cast<int>(k), paths.back());
  }
  return paths;
}

}  // namespace cmbrl

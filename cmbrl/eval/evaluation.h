// Evaluating a trained run: episodes of its MPC agent with the models of its last checkpoint,
// with what pictures need, the planner's predicted trajectories included.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/eval/rollout.h"
#include "cmbrl/learners/learner_inputs.h"
#include "cmbrl/viz/scene_picture.h"

namespace cmbrl {

struct EvaluationOptions {
  int episodes = 1;
  std::uint64_t seed = 0;  // environment and planner
  // false: only the first episode's reset is seeded, later ones continue its generator. true:
  // episode k is reset with seed + k, so its layout is the same whatever happened before (two
  // planners meet the same layouts).
  bool reseed_each_episode = false;
  int predictions_every = 25;  // record the planner's predictions every this many steps (0: never)
  int predicted_samples = 8;   // sample trajectories kept per recorded step (each x members)
  // Keep the environment's own pictures (EpisodeRecord::frames) after the reset, every this
  // many steps and at the end (0: none).
  int frame_every = 0;
  // "section.key=value" changes of the planner, its objective or the classifier's threshold,
  // for this evaluation only (LoadedRun::PlanningOverrideKeys).
  std::vector<std::string> overrides;
};

struct EvaluatedEpisode {
  EpisodeRecord record;
  std::vector<PredictedPath> predictions;  // world coordinates, at the recorded steps
  double mean_ms_per_plan = 0.0;
  // MPC runs only: the mean feasible fraction of the plans' last populations, and the share of
  // steps whose executed plan came from infeasible elites (RCE's fallback: too few feasible
  // samples).
  std::optional<double> mean_feasible_fraction;
  std::optional<double> fallback_step_fraction;
};

// An evaluation drawn from the environment's own pictures (a Python environment's) keeps one
// every this many steps (EvaluationOptions::frame_every).
inline constexpr int kFrameEvery = 25;

// Draws each episode k as `folder`/episode-<k>.png (the folder made): the arena with its path,
// goals and the recorded plans; or the environment's own pictures side by side (at most 8,
// evenly spaced, the first and the last kept), under its return and cost. Returns the paths.
// Throws cmbrl::Error, before anything is written, unless every episode can be drawn (a task
// file's have neither an arena nor pictures of their own), and for a file that cannot be
// written.
std::vector<std::string> WriteEpisodePictures(const std::vector<EvaluatedEpisode>& episodes,
                                              const std::string& folder);

class MpcAgent;

// The agent's last plan in world coordinates: every sampled action sequence of the plan's last
// iteration and the executed plan, each as every ensemble member predicted it.
struct PlanPaths {
  int members = 0;                       // E
  std::vector<PredictedPath> population;  // (N * E): sample n, member e at n * E + e
  std::vector<PredictedPath> chosen;      // (E): the executed plan (chosen = true)
};

// Takes the agent's last plan's paths. `scene` is the one the plan was made in; `spec` the
// environment's observation spec. Rolls the executed plan through the objective once more, so the
// objective's last values change: take them once per plan (after Act), then select from them.
PlanPaths TakePlanPaths(MpcAgent& agent, const BoxSpec& spec, const SceneState& scene);

// `samples` sampled sequences spread evenly over the population (all of them when it has fewer),
// each with every member's path, then the executed plan's: (min(samples, N) + 1) * E paths.
std::vector<PredictedPath> SelectPredictions(const PlanPaths& paths, int samples);

// SelectPredictions(TakePlanPaths(...), samples), for pictures of an evaluation.
std::vector<PredictedPath> PlannerPredictions(MpcAgent& agent, const BoxSpec& spec,
                                              const SceneState& scene, int samples);

// Loads run_dir's config and checkpoint and runs the episodes. `inputs`: what the run needs
// beside its files (a Python environment, reward or termination). Throws cmbrl::Error when
// run_dir holds no trained run.
std::vector<EvaluatedEpisode> EvaluateRun(const std::string& run_dir,
                                          const EvaluationOptions& options,
                                          const LearnerInputs& inputs = {});

}  // namespace cmbrl

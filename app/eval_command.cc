// `cmbrl eval`: episodes of a trained run's agent (MPC or model-free), one JSON line each, and
// top-down pictures (an MPC agent's with the planner's predicted trajectories).
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>

#include "app/arguments.h"
#include "app/commands.h"
#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/eval/evaluation.h"
#include "cmbrl/eval/rollout.h"
#include "cmbrl/run/run_directory.h"
#include "cmbrl/viz/scene_picture.h"

namespace cmbrl::app {
namespace {

struct EvalArgs {
  std::string run;
  EvaluationOptions options;
  std::string render;
};

// --render draws the Goal world's arena or a Python environment's own pictures: a task file,
// which has neither, is refused before it runs.
void RequirePicturesToRender(const EvalArgs& args) {
  if (args.render.empty()) return;
  const RunDirectory run(args.run);
  if (!run.HoldsRun()) return;  // EvaluateRun names it
  const TrainConfig config = LoadTrainConfig(run.config_file().string());
  Require(!IsDeclaredTask(config.mujoco_task),
          "--render draws the Goal world's arena, or a Python environment's own pictures: task "
          "'{}' has neither (evaluate it without --render)",
          config.task);
}

void RunEval(const EvalArgs& args) {
  RequirePicturesToRender(args);
  EvaluationOptions options = args.options;
  if (!args.render.empty()) options.frame_every = kFrameEvery;
  const std::vector<EvaluatedEpisode> episodes = EvaluateRun(args.run, options);
  std::vector<std::string> pictures;
  if (!args.render.empty()) {
    try {
      pictures = WriteEpisodePictures(episodes, args.render);
    } catch (const Error& error) {
      Fail("--render: {}", error.what());
    }
  }
  for (size_t k = 0; k < episodes.size(); ++k) {
    const EvaluatedEpisode& episode = episodes[k];
    const EpisodeRecord& r = episode.record;
    nlohmann::ordered_json line = {{"run", args.run},        {"seed", args.options.seed},
                                   {"episode", k},           {"return", r.episode_return},
                                   {"cost", r.episode_cost}, {"steps", r.steps}};
    for (const NamedFigure& figure : NavigationFigures(r)) {
      std::visit([&](auto value) { line[figure.name] = value; }, figure.value);
    }
    line["ms_per_plan"] = episode.mean_ms_per_plan;
    if (episode.mean_feasible_fraction) {
      line["feasible_fraction"] = *episode.mean_feasible_fraction;
      line["fallback_steps"] = *episode.fallback_step_fraction;
    }
    if (!args.options.overrides.empty()) line["overrides"] = args.options.overrides;
    if (!pictures.empty()) line["picture"] = pictures[k];
    std::cout << line.dump() << std::endl;
  }
}

}  // namespace

void AddEvalCommand(CLI::App& parent) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* command = parent.add_subcommand(
      "eval", "Evaluate a trained run's agent; print one JSON line per episode; draw them");
  command->add_option("--run", args->run, "run directory (from cmbrl train)")->required();
  command->add_option("--episodes", args->options.episodes, "episodes")
      ->check(IntegerIn(1, 1'000'000))
      ->capture_default_str();
  command->add_option("--seed", args->options.seed, "seed of the environment and the planner")
      ->check(SeedInteger())
      ->capture_default_str();
  command->add_option("--render", args->render, "folder for one PNG per episode");
  command->add_flag("--reseed", args->options.reseed_each_episode,
                    "reset episode k with seed + k (the same layouts whatever the agent does), "
                    "not only the first episode");
  command->add_option(
      "--set", args->options.overrides,
      "SECTION.KEY=VALUE: use the trained models with another planner, objective "
      "or classifier threshold (planning.*, objective.*, classifier.threshold, planner), "
      "e.g. --set planning.population=500 classifier.threshold=0.3");
  command
      ->add_option("--predictions-every", args->options.predictions_every,
                   "draw the planner's predicted trajectories every this many steps (0: none)")
      ->check(IntegerIn(0, 1'000'000))
      ->capture_default_str();
  command->callback([args] { RunEval(*args); });
}

}  // namespace cmbrl::app

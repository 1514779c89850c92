// `cmbrl rollout`: runs episodes of a fixed policy, prints one JSON object per episode and
// optionally draws each episode from above.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "app/arguments.h"
#include "app/commands.h"
#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/env/tasks/task_spec.h"
#include "cmbrl/eval/rollout.h"
#include "cmbrl/viz/scene_picture.h"

namespace cmbrl::app {
namespace {

struct RolloutArgs {
  std::string task = "PointGoal1";
  std::string variant;  // "": the task's default (DefaultVariant)
  std::string policy = "random";
  int episodes = 1;
  std::uint64_t seed = 0;
  std::string render;
  int picture_size = 800;  // pixels
  std::string trace;
};

// Forwards to an environment and writes every reset and step as one JSON line: the episode, the
// action, the observation, reward, cost and flags, doubles at full precision (round-trip).
class TracingEnv final : public Env {
 public:
  TracingEnv(Env& env, std::ostream& out) : env_(env), out_(out) {}
  std::vector<double> Reset(std::optional<std::uint64_t> seed) override {
    std::vector<double> observation = env_.Reset(seed);
    ++episode_;
    nlohmann::ordered_json line = {{"episode", episode_}, {"reset", true}};
    line["seed"] = seed ? nlohmann::json(*seed) : nlohmann::json(nullptr);
    line["observation"] = observation;
    out_ << line.dump() << "\n";
    return observation;
  }
  StepResult Step(const std::vector<double>& action) override {
    StepResult step = env_.Step(action);
    const nlohmann::ordered_json line = {
        {"episode", episode_},        {"action", action},           {"observation", step.observation},
        {"reward", step.reward},      {"cost", step.cost},          {"terminated", step.terminated},
        {"truncated", step.truncated}};
    out_ << line.dump() << "\n";
    return step;
  }
  const BoxSpec& observation_spec() const override { return env_.observation_spec(); }
  const BoxSpec& action_spec() const override { return env_.action_spec(); }
  int max_episode_steps() const override { return env_.max_episode_steps(); }
  std::string State() const override { return env_.State(); }
  void SetState(const std::string& state) override { env_.SetState(state); }
  double agent_step_seconds() const override { return env_.agent_step_seconds(); }
  const SceneSource* scene_source() const override { return env_.scene_source(); }
  std::string GeneratorState() const override { return env_.GeneratorState(); }
  void SetGeneratorState(const std::string& state) override { env_.SetGeneratorState(state); }

 private:
  Env& env_;
  std::ostream& out_;
  int episode_ = -1;
};

// out.png for a single episode; out-ep0.png, out-ep1.png, ... for several.
std::string PicturePath(const std::string& render, int episode, int episodes) {
  if (episodes == 1) return render;
  const std::filesystem::path path(render);
  return (path.parent_path() /
          fmt::format("{}-ep{}{}", path.stem().string(), episode, path.extension().string()))
      .string();
}

void RunRollout(const RolloutArgs& args) {
  const Variant variant =
      args.variant.empty() ? DefaultVariant(FindTask(args.task)) : ParseVariant(args.variant);
  std::unique_ptr<Env> made = MakeEnv(args.task, variant);
  std::ofstream trace_file;
  std::unique_ptr<Env> tracing;
  if (!args.trace.empty()) {
    trace_file.open(args.trace);
    Require(trace_file.good(), "--trace '{}': cannot write this file", args.trace);
    tracing = std::make_unique<TracingEnv>(*made, trace_file);
  }
  Env* env = tracing ? tracing.get() : made.get();
  // The policy draws from its own stream of the seed, apart from the environment's.
  std::unique_ptr<Policy> policy =
      MakePolicy(args.policy, env->action_spec(), DeriveSeed(args.seed, 1));
  for (int episode = 0; episode < args.episodes; ++episode) {
    // The first reset seeds the environment; later ones continue its generator (Gymnasium).
    const std::optional<std::uint64_t> reset_seed =
        episode == 0 ? std::optional<std::uint64_t>(args.seed) : std::nullopt;
    const EpisodeRecord record = RunEpisode(*env, *policy, reset_seed);
    nlohmann::ordered_json line = {
        {"task", args.task},
        {"variant", VariantName(variant)},
        {"policy", args.policy},
        {"seed", args.seed},
        {"episode", episode},
        {"return", record.episode_return},
        {"cost", record.episode_cost},
        {"steps", record.steps},
        {"env_steps", record.env_steps},
        {"goals_met", record.goals_met},
        {"terminated", record.terminated},
        {"truncated", record.truncated},
        {"obs_dim", env->observation_spec().size()},
        {"act_dim", env->action_spec().size()},
    };
    if (!args.render.empty()) {
      const std::string picture_path = PicturePath(args.render, episode, args.episodes);
      ScenePicture picture{
          record.final_scene,
          record.path,
          record.path_violations,
          record.reached_goals,
          fmt::format("{} ({}) {} policy, seed {}, episode {}: return {:.2f}, "
                      "cost {}, goals {}",
                      args.task, VariantName(variant), args.policy, args.seed, episode,
                      record.episode_return, record.episode_cost, record.goals_met),
          {}};
      ScenePictureOptions options;
      options.size_px = args.picture_size;
      WriteScenePng(picture, picture_path, options);
      line["picture"] = picture_path;
    }
    // A trace cut short by a full disk stops the rollout at this episode, naming the file.
    if (tracing && trace_file.fail()) CloseChecked(trace_file, args.trace);
    std::cout << line.dump() << std::endl;
  }
  if (tracing) CloseChecked(trace_file, args.trace);
}

}  // namespace

void AddRolloutCommand(CLI::App& parent) {
  auto args = std::make_shared<RolloutArgs>();
  CLI::App* command = parent.add_subcommand(
      "rollout", "Run episodes of a fixed policy; print one JSON object per episode");
  command->add_option("--task", args->task, fmt::format("one of {}", fmt::join(EnvNames(), ", ")))
      ->capture_default_str();
  command->add_option("--variant", args->variant,
                      "paper, paper-lidar or standard (default: paper for the paper's Goal tasks, "
                      "standard for the others)");
  command->add_option("--policy", args->policy, "random or zero")->capture_default_str();
  command->add_option("--episodes", args->episodes, "number of episodes")
      ->check(IntegerIn(1, 1'000'000))
      ->capture_default_str();
  command->add_option("--seed", args->seed, "seed of the environment and the policy")
      ->check(SeedInteger())
      ->capture_default_str();
  command->add_option("--render", args->render,
                      "write a top-down PNG of each episode here (FILE, or FILE-epK.png when "
                      "several)");
  command->add_option("--picture-size", args->picture_size, "the picture's width in pixels")
      ->check(IntegerIn(64, 8192))
      ->capture_default_str();
  command->add_option("--trace", args->trace,
                      "write every reset and step here as JSON lines (action, observation, reward, "
                      "cost), doubles at full precision");
  command->callback([args] { RunRollout(*args); });
}

}  // namespace cmbrl::app

#include "cmbrl/experiment/trainer.h"

#include <fmt/format.h>
#include <torch/torch.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "cmbrl/agent/mpc_agent.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/run_lock.h"
#include "cmbrl/env/goal_env.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/transition_buffer.h"
#include "cmbrl/models/xgboost_cost_model.h"

namespace cmbrl {
namespace fs = std::filesystem;

namespace {

constexpr const char* kConfigFile = "config.yaml";
constexpr const char* kProgressFile = "progress.csv";
constexpr const char* kCheckpointDir = "checkpoint";

std::string Number(double value) { return std::isfinite(value) ? fmt::format("{}", value) : "nan"; }

}  // namespace

std::string ProgressCsvHeader() {
  return "Epoch,Episode,EpRet,EpCost,TotalEnvInteracts,PretrainInteracts,Time,DynamicsValMSE,"
         "ClassifierSafeAcc,ClassifierUnsafeAcc,FeasibleFraction,MsPerPlan,Steps,GoalsMet";
}

std::string ProgressCsvLine(const ProgressRow& r) {
  return fmt::format("{},{},{},{},{},{},{:.3f},{},{},{},{},{:.3f},{},{}", r.epoch, r.episode,
                     Number(r.episode_return), Number(r.episode_cost), r.total_env_interacts,
                     r.pretrain_interacts, r.time_seconds, Number(r.dynamics_validation_mse),
                     Number(r.classifier_safe_accuracy), Number(r.classifier_unsafe_accuracy),
                     Number(r.feasible_fraction), r.ms_per_plan, r.steps, r.goals_met);
}

struct Trainer::State {
  TrainConfig config;
  fs::path run_dir;
  std::unique_ptr<RunLock> lock;  // held for the trainer's lifetime
  std::unique_ptr<GoalEnv> env;
  std::unique_ptr<TransitionBuffer> transitions;
  std::unique_ptr<LabeledStateBuffer> labeled;
  std::unique_ptr<EnsembleDynamics> ensemble;
  std::unique_ptr<XgbCostModel> classifier;
  std::unique_ptr<MpcAgent> agent;

  // Counters, all in the checkpoint.
  bool pretrained = false;
  int episodes = 0;
  int rows = 0;
  std::int64_t total_steps = 0;
  std::int64_t pretrain_steps = 0;
  double elapsed_before = 0.0;  // seconds of earlier sessions of this run
  EnsembleFitReport last_dynamics_fit;
  CostFitReport last_classifier_fit;
  std::chrono::steady_clock::time_point session_start = std::chrono::steady_clock::now();

  explicit State(TrainConfig c, fs::path dir) : config(std::move(c)), run_dir(std::move(dir)) {
    const std::uint64_t seed = config.seed;
    env = std::make_unique<GoalEnv>(GoalTaskSpecByName(config.task, ParseVariant(config.variant)));
    const int state_dim = env->observation_spec().size();
    const int action_dim = env->action_spec().size();
    const TrainingLoopOptions& t = config.training;
    transitions = std::make_unique<TransitionBuffer>(state_dim, action_dim, t.transition_capacity);
    labeled = std::make_unique<LabeledStateBuffer>(state_dim, t.safe_capacity, t.unsafe_capacity);
    ensemble = std::make_unique<EnsembleDynamics>(state_dim, action_dim, config.ensemble,
                                                  DeriveSeed(seed, kEnsembleSeedStream));
    classifier = std::make_unique<XgbCostModel>(state_dim, config.classifier,
                                                DeriveSeed(seed, kClassifierSeedStream));
    PlannerSettings planning = config.planning;
    planning.problem.action_dim = action_dim;
    agent = std::make_unique<MpcAgent>(*ensemble, *classifier, config.planner, planning,
                                       config.objective, DeriveSeed(seed, kPlannerSeedStream));
    last_dynamics_fit.validation_mse = std::numeric_limits<double>::quiet_NaN();
    last_classifier_fit.safe_accuracy = std::numeric_limits<double>::quiet_NaN();
    last_classifier_fit.unsafe_accuracy = std::numeric_limits<double>::quiet_NaN();
  }

  double Elapsed() const {
    return elapsed_before +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - session_start).count();
  }

  // Facts B6: random actions, each episode cut after pretrain_steps stored transitions.
  void Pretrain() {
    RandomPolicy random(env->action_spec(), DeriveSeed(config.seed, kPretrainSeedStream));
    for (int episode = 0; episode < config.training.pretrain_episodes; ++episode) {
      std::vector<double> observation =
          episode == 0 ? env->Reset(DeriveSeed(config.seed, kEnvSeedStream)) : env->Reset();
      int stored = 0;
      while (stored < config.training.pretrain_steps) {
        const std::vector<double> action = random.Act(observation);
        StepResult step = env->Step(action);
        ++pretrain_steps;
        const bool end = step.terminated || step.truncated;
        const bool kept =
            transitions->Add(observation, action, step.observation, step.info.goal_met, end);
        stored += kept;
        AddLabel(step, kept);
        observation = std::move(step.observation);
        if (end) break;
      }
    }
    FitModels();
    pretrained = true;
  }

  // The classifier's label of this step's next state: only beside a stored transition unless
  // label_every_step (facts B4).
  void AddLabel(const StepResult& step, bool transition_kept) {
    if (transition_kept || config.training.label_every_step)
      labeled->Add(step.observation, step.cost > 0.0);
  }

  void FitModels() {
    last_dynamics_fit = ensemble->Fit(*transitions);
    last_classifier_fit = classifier->Fit(*labeled);
  }

  // One MPC episode; its row.
  ProgressRow Episode() {
    std::vector<double> observation = config.training.pretrain_episodes == 0 && episodes == 0
                                          ? env->Reset(DeriveSeed(config.seed, kEnvSeedStream))
                                          : env->Reset();
    agent->BeginEpisode();
    ProgressRow row;
    double feasible = 0.0, milliseconds = 0.0;
    for (;;) {
      const std::vector<double> action = agent->Act(observation);
      feasible += agent->last_plan().feasible_fraction;
      milliseconds += agent->last_plan().milliseconds;
      StepResult step = env->Step(action);
      const bool end = step.terminated || step.truncated;
      const bool kept =
          transitions->Add(observation, action, step.observation, step.info.goal_met, end);
      AddLabel(step, kept);
      ++total_steps;
      ++row.steps;
      row.episode_return += step.reward;
      row.episode_cost += step.cost;
      row.goals_met += step.info.goal_met;
      observation = std::move(step.observation);
      if (end) break;
    }
    ++episodes;
    row.episode = episodes;
    row.epoch = (episodes - 1) / config.training.episodes_per_epoch + 1;
    row.total_env_interacts = total_steps;
    row.pretrain_interacts = pretrain_steps;
    row.dynamics_validation_mse = last_dynamics_fit.validation_mse;
    row.classifier_safe_accuracy = last_classifier_fit.safe_accuracy;
    row.classifier_unsafe_accuracy = last_classifier_fit.unsafe_accuracy;
    row.feasible_fraction = feasible / row.steps;
    row.ms_per_plan = milliseconds / row.steps;
    row.time_seconds = Elapsed();
    return row;
  }

  void AppendRow(const ProgressRow& row) {
    std::ofstream out(run_dir / kProgressFile, std::ios::app);
    out << ProgressCsvLine(row) << "\n";
    out.close();
    Require(!out.fail(), "could not append to '{}'", (run_dir / kProgressFile).string());
    ++rows;
  }

  // Writes everything into checkpoint.tmp/, then swaps it in: a stop at any moment leaves either
  // the old or the new checkpoint whole.
  void WriteCheckpoint(bool models_changed) {
    const fs::path final_dir = run_dir / kCheckpointDir;
    const fs::path tmp = run_dir / "checkpoint.tmp";
    const fs::path old = run_dir / "checkpoint.old";
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    transitions->Save((tmp / "transitions.bin").string());
    labeled->Save((tmp / "labeled_states.bin").string());
    if (models_changed || !fs::exists(final_dir / "ensemble.pt")) {
      ensemble->Save((tmp / "ensemble.pt").string());
      classifier->Save((tmp / "classifier.json").string());
    } else {
      // Unchanged since the last fit, and files of a checkpoint are never rewritten in place:
      // a hard link carries them over without copying (about 50 MB at the paper's sizes).
      for (const char* name : {"ensemble.pt", "classifier.json"}) {
        std::error_code linked;
        fs::create_hard_link(final_dir / name, tmp / name, linked);
        if (linked) fs::copy_file(final_dir / name, tmp / name);
      }
    }
    torch::save(agent->planner().GeneratorState(), (tmp / "planner_generator.pt").string());
    const nlohmann::json state = {
        {"pretrained", pretrained},
        {"episodes", episodes},
        {"rows", rows},
        {"total_steps", total_steps},
        {"pretrain_steps", pretrain_steps},
        {"elapsed_seconds", Elapsed()},
        {"env_generator", env->GeneratorState()},
        {"dynamics_validation_mse", Number(last_dynamics_fit.validation_mse)},
        {"classifier_safe_accuracy", Number(last_classifier_fit.safe_accuracy)},
        {"classifier_unsafe_accuracy", Number(last_classifier_fit.unsafe_accuracy)},
    };
    std::ofstream(tmp / "state.json") << state.dump(2);
    fs::remove_all(old);
    if (fs::exists(final_dir)) fs::rename(final_dir, old);
    fs::rename(tmp, final_dir);
    fs::remove_all(old);
  }

  void ReadCheckpoint(const fs::path& dir) {
    std::ifstream in(dir / "state.json");
    nlohmann::json state;
    in >> state;
    pretrained = state.at("pretrained");
    episodes = state.at("episodes");
    rows = state.at("rows");
    total_steps = state.at("total_steps");
    pretrain_steps = state.at("pretrain_steps");
    elapsed_before = state.at("elapsed_seconds");
    env->SetGeneratorState(state.at("env_generator"));
    last_dynamics_fit.validation_mse =
        std::stod(state.at("dynamics_validation_mse").get<std::string>());
    last_classifier_fit.safe_accuracy =
        std::stod(state.at("classifier_safe_accuracy").get<std::string>());
    last_classifier_fit.unsafe_accuracy =
        std::stod(state.at("classifier_unsafe_accuracy").get<std::string>());
    transitions->Load((dir / "transitions.bin").string());
    labeled->Load((dir / "labeled_states.bin").string());
    ensemble->Load((dir / "ensemble.pt").string());
    classifier->Load((dir / "classifier.json").string());
    torch::Tensor generator;
    torch::load(generator, (dir / "planner_generator.pt").string());
    agent->planner().SetGeneratorState(generator);
  }

  // Keeps the header and the first `rows` lines of progress.csv.
  void TruncateProgress() {
    const fs::path path = run_dir / kProgressFile;
    std::ifstream in(path);
    std::string kept, line;
    for (int i = 0; i <= rows && std::getline(in, line); ++i) kept += line + "\n";
    in.close();
    std::ofstream(path, std::ios::trunc) << (kept.empty() ? ProgressCsvHeader() + "\n" : kept);
  }
};

std::unique_ptr<Trainer> Trainer::Start(const TrainConfig& config, const std::string& run_dir) {
  ValidateTrainConfig(config, "(command line)");
  const fs::path dir(run_dir);
  Require(!fs::exists(dir / kConfigFile),
          "'{}' already holds a run: resume it with --resume, or choose another directory",
          run_dir);
  fs::create_directories(dir);
  auto lock = std::make_unique<RunLock>(run_dir);
  Require(!fs::exists(dir / kConfigFile),
          "'{}' already holds a run: resume it with --resume, or choose another directory",
          run_dir);
  std::ofstream(dir / kProgressFile, std::ios::trunc) << ProgressCsvHeader() << "\n";
  // config.yaml marks the run as existing: written whole, then renamed into place.
  const fs::path tmp = dir / "config.yaml.tmp";
  std::ofstream(tmp) << TrainConfigToYaml(config);
  fs::rename(tmp, dir / kConfigFile);
  auto state = std::make_unique<State>(config, dir);
  state->lock = std::move(lock);
  return std::unique_ptr<Trainer>(new Trainer(std::move(state)));
}

std::unique_ptr<Trainer> Trainer::Resume(const std::string& run_dir) {
  const fs::path dir(run_dir);
  Require(fs::exists(dir / kConfigFile), "'{}' holds no run (no {}): start one with --config",
          run_dir, kConfigFile);
  auto lock = std::make_unique<RunLock>(run_dir);
  auto state = std::make_unique<State>(LoadTrainConfig((dir / kConfigFile).string()), dir);
  state->lock = std::move(lock);
  // A stop between the two renames of WriteCheckpoint leaves only checkpoint.old.
  fs::path checkpoint = dir / kCheckpointDir;
  if (!fs::exists(checkpoint) && fs::exists(dir / "checkpoint.old"))
    checkpoint = dir / "checkpoint.old";
  if (fs::exists(checkpoint / "state.json")) state->ReadCheckpoint(checkpoint);
  state->TruncateProgress();
  return std::unique_ptr<Trainer>(new Trainer(std::move(state)));
}

Trainer::Trainer(std::unique_ptr<State> state) : state_(std::move(state)) {}
Trainer::~Trainer() = default;

const TrainConfig& Trainer::config() const { return state_->config; }
std::int64_t Trainer::total_env_interacts() const { return state_->total_steps; }

void Trainer::Run(const std::function<void(const ProgressRow&)>& on_episode) {
  State& s = *state_;
  if (!s.pretrained) {
    s.Pretrain();
    s.WriteCheckpoint(/*models_changed=*/true);
  }
  while (s.total_steps < s.config.training.total_steps) {
    const ProgressRow row = s.Episode();
    s.AppendRow(row);
    if (on_episode) on_episode(row);
    const bool refit = s.episodes % s.config.training.episodes_per_epoch == 0;
    if (refit) s.FitModels();
    s.WriteCheckpoint(refit);
  }
}

}  // namespace cmbrl

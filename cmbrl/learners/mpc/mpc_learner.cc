#include "cmbrl/learners/mpc/mpc_learner.h"

#include <chrono>

#include <fmt/format.h>
#include <torch/torch.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "cmbrl/core/torch_util.h"
#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/run/learner_state.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The checkpoint's files.
constexpr const char* kTransitionsFile = "transitions.bin";
constexpr const char* kLabeledStatesFile = "labeled_states.bin";
constexpr const char* kEnsembleFile = "ensemble.pt";
constexpr const char* kClassifierFile = "classifier.json";
constexpr const char* kPlannerGeneratorFile = "planner_generator.pt";
constexpr const char* kStateFile = "state.json";

std::string Fixed3(double value) { return fmt::format("{:.3f}", value); }

}  // namespace

const std::vector<ProgressColumn<ProgressRow>>& MpcProgressColumns() {
  using R = ProgressRow;
  static const std::vector<ProgressColumn<ProgressRow>> columns = {
      {"Epoch", [](const R& r) { return std::to_string(r.epoch); }},
      {"Episode", [](const R& r) { return std::to_string(r.episode); }},
      {kEpRetColumn, [](const R& r) { return ProgressNumber(r.episode_return); }},
      {kEpCostColumn, [](const R& r) { return ProgressNumber(r.episode_cost); }},
      {kTotalEnvInteractsColumn, [](const R& r) { return std::to_string(r.total_env_interacts); }},
      {"PretrainInteracts", [](const R& r) { return std::to_string(r.pretrain_interacts); }},
      {kTimeColumn, [](const R& r) { return Fixed3(r.time_seconds); }},
      {"DynamicsValMSE", [](const R& r) { return ProgressNumber(r.dynamics_validation_mse); }},
      {"ClassifierSafeAcc", [](const R& r) { return ProgressNumber(r.classifier_safe_accuracy); }},
      {"ClassifierUnsafeAcc",
       [](const R& r) { return ProgressNumber(r.classifier_unsafe_accuracy); }},
      {kFeasibleFractionColumn, [](const R& r) { return ProgressNumber(r.feasible_fraction); }},
      {"MsPerPlan", [](const R& r) { return Fixed3(r.ms_per_plan); }},
      {kStepsColumn, [](const R& r) { return std::to_string(r.steps); }},
      {"GoalsMet", [](const R& r) { return std::to_string(r.goals_met); }},
      // Added after the columns above: a run begun without them keeps its columns on resume.
      {kHazardStepsColumn, [](const R& r) { return std::to_string(r.hazard_steps); }},
      {kVaseStepsColumn, [](const R& r) { return std::to_string(r.vase_steps); }},
  };
  return columns;
}

std::string ProgressCsvHeader() { return ProgressHeader(MpcProgressColumns()); }

std::string ProgressCsvLine(const ProgressRow& row) { return ProgressLine(MpcProgressColumns(), row); }

void LoadMpcModels(const fs::path& checkpoint, MpcParts& parts) {
  parts.ensemble->Load((checkpoint / kEnsembleFile).string());
  parts.classifier->Load((checkpoint / kClassifierFile).string());
}

MpcLearner::MpcLearner(TrainConfig config)
    : config_(std::move(config)),
      parts_(AssembleMpc(config_, RunSeeds(config_.seed))),
      dynamics_validation_mse_(kNaN),
      classifier_safe_accuracy_(kNaN),
      classifier_unsafe_accuracy_(kNaN) {
  const int state_dim = parts_.env->observation_spec().size();
  const int action_dim = parts_.env->action_spec().size();
  const TrainingLoopOptions& t = config_.training;
  transitions_ = std::make_unique<TransitionBuffer>(state_dim, action_dim, t.transition_capacity);
  labeled_ = std::make_unique<LabeledStateBuffer>(state_dim, t.safe_capacity, t.unsafe_capacity);
}

namespace {

// Adds the seconds `work` takes to `total` and returns its result.
template <typename Work>
auto Timed(double& total, Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  struct Add {
    double& total;
    std::chrono::steady_clock::time_point start;
    ~Add() {
      total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  } add{total, start};
  return work();
}

}  // namespace

MpcLearner::~MpcLearner() = default;

bool MpcLearner::Finished() const {
  return pretrained_ && total_steps_ >= config_.training.total_steps;
}

LearnerStep MpcLearner::Advance(const std::function<double()>& elapsed_seconds) {
  LearnerStep step;
  if (!pretrained_) {
    Pretrain();
    step.summary = {0, total_steps_, budget(), 0.0, 0.0, elapsed_seconds()};
    return step;
  }
  step.models_changed = models_due_;
  if (models_due_) {  // the run was continued past the budget it had stopped at
    FitModels();
    models_due_ = false;
  }
  last_row_ = Episode(elapsed_seconds);
  step.row = ProgressCsvLine(last_row_);
  if (episodes_ % config_.training.episodes_per_epoch == 0) {
    if (Finished()) {
      models_due_ = true;
    } else {
      FitModels();
      step.models_changed = true;
    }
  }
  step.summary = {last_row_.epoch,          total_steps_,
                  budget(),                 last_row_.episode_return,
                  last_row_.episode_cost,   last_row_.time_seconds};
  return step;
}

// Facts B6: random actions, each episode cut after pretrain_steps stored transitions.
void MpcLearner::Pretrain() {
  Env& env = *parts_.env;
  RandomPolicy random(env.action_spec(), DeriveSeed(config_.seed, kPretrainSeedStream));
  for (int episode = 0; episode < config_.training.pretrain_episodes; ++episode) {
    std::vector<double> observation =
        episode == 0 ? env.Reset(DeriveSeed(config_.seed, kEnvSeedStream)) : env.Reset();
    int stored = 0;
    while (stored < config_.training.pretrain_steps) {
      const std::vector<double> action = random.Act(observation);
      StepResult step = Timed(environment_seconds_, [&] { return env.Step(action); });
      ++pretrain_steps_;
      const bool end = step.terminated || step.truncated;
      const bool kept =
          transitions_->Add(observation, action, step.observation, step.info.goal_met, end);
      stored += kept;
      AddLabel(step.observation, step.cost, kept);
      observation = std::move(step.observation);
      if (end) break;
    }
  }
  FitModels();
  pretrained_ = true;
}

// The classifier's label of a step's next state: only beside a stored transition unless
// label_every_step (facts B4).
void MpcLearner::AddLabel(const std::vector<double>& next_state, double cost,
                          bool transition_kept) {
  if (transition_kept || config_.training.label_every_step) labeled_->Add(next_state, cost > 0.0);
}

std::vector<std::pair<std::string, double>> MpcLearner::TimeSplit() const {
  return {{"planning", planning_seconds_},
          {"environment", environment_seconds_},
          {"dynamics_fits", dynamics_fit_seconds_},
          {"classifier_fits", classifier_fit_seconds_}};
}

void MpcLearner::FitModels() {
  dynamics_validation_mse_ =
      Timed(dynamics_fit_seconds_, [&] { return parts_.ensemble->Fit(*transitions_); })
          .validation_mse;
  const CostFitReport classifier =
      Timed(classifier_fit_seconds_, [&] { return parts_.classifier->Fit(*labeled_); });
  classifier_safe_accuracy_ = classifier.safe_accuracy;
  classifier_unsafe_accuracy_ = classifier.unsafe_accuracy;
}

ProgressRow MpcLearner::Episode(const std::function<double()>& elapsed_seconds) {
  Env& env = *parts_.env;
  MpcAgent& agent = *parts_.agent;
  std::vector<double> observation = config_.training.pretrain_episodes == 0 && episodes_ == 0
                                        ? env.Reset(DeriveSeed(config_.seed, kEnvSeedStream))
                                        : env.Reset();
  agent.BeginEpisode();
  ProgressRow row;
  double feasible = 0.0, milliseconds = 0.0;
  for (;;) {
    const std::vector<double> action =
        Timed(planning_seconds_, [&] { return agent.Act(observation); });
    feasible += agent.last_plan().feasible_fraction;
    milliseconds += agent.last_plan().milliseconds;
    StepResult step = Timed(environment_seconds_, [&] { return env.Step(action); });
    const bool end = step.terminated || step.truncated;
    const bool kept =
        transitions_->Add(observation, action, step.observation, step.info.goal_met, end);
    AddLabel(step.observation, step.cost, kept);
    ++total_steps_;
    ++row.steps;
    row.episode_return += step.reward;
    row.episode_cost += step.cost;
    row.goals_met += step.info.goal_met;
    row.hazard_steps += step.info.cost_hazards > 0.0;
    row.vase_steps += step.info.cost_vases_contact > 0.0 || step.info.cost_vases_velocity > 0.0;
    observation = std::move(step.observation);
    if (end) break;
  }
  ++episodes_;
  row.episode = episodes_;
  row.epoch = (episodes_ - 1) / config_.training.episodes_per_epoch + 1;
  row.total_env_interacts = total_steps_;
  row.pretrain_interacts = pretrain_steps_;
  row.dynamics_validation_mse = dynamics_validation_mse_;
  row.classifier_safe_accuracy = classifier_safe_accuracy_;
  row.classifier_unsafe_accuracy = classifier_unsafe_accuracy_;
  row.feasible_fraction = feasible / row.steps;
  row.ms_per_plan = milliseconds / row.steps;
  row.time_seconds = elapsed_seconds();
  return row;
}

void MpcLearner::Save(const fs::path& folder, const fs::path& previous,
                      bool models_changed) const {
  transitions_->Save((folder / kTransitionsFile).string());
  labeled_->Save((folder / kLabeledStatesFile).string());
  if (models_changed || previous.empty() || !fs::exists(previous / kEnsembleFile)) {
    parts_.ensemble->Save((folder / kEnsembleFile).string());
    parts_.classifier->Save((folder / kClassifierFile).string());
  } else {
    // Unchanged since the last fit: a hard link carries them over without copying (about 50 MB
    // at the paper's sizes).
    for (const char* name : {kEnsembleFile, kClassifierFile}) {
      std::error_code linked;
      fs::create_hard_link(previous / name, folder / name, linked);
      if (linked) fs::copy_file(previous / name, folder / name);
    }
  }
  SaveTensor(parts_.agent->planner().GeneratorState(),
             (folder / kPlannerGeneratorFile).string());
  const nlohmann::json state = {
      {"pretrained", pretrained_},
      {"models_due", models_due_},
      {"episodes", episodes_},
      {"total_steps", total_steps_},
      {"pretrain_steps", pretrain_steps_},
      {"env_generator", parts_.env->GeneratorState()},
      {"dynamics_validation_mse", ProgressNumber(dynamics_validation_mse_)},
      {"classifier_safe_accuracy", ProgressNumber(classifier_safe_accuracy_)},
      {"classifier_unsafe_accuracy", ProgressNumber(classifier_unsafe_accuracy_)},
  };
  WriteLearnerState(folder / kStateFile, state);
}

void MpcLearner::Load(const fs::path& folder) {
  ReadLearnerState(folder / kStateFile, [&](const nlohmann::json& state) {
    pretrained_ = state.at("pretrained").get<bool>();
    models_due_ = state.value("models_due", false);  // absent before v0.3
    episodes_ = state.at("episodes").get<int>();
    total_steps_ = state.at("total_steps").get<std::int64_t>();
    pretrain_steps_ = state.at("pretrain_steps").get<std::int64_t>();
    parts_.env->SetGeneratorState(state.at("env_generator").get<std::string>());
    dynamics_validation_mse_ = StateNumber(state, "dynamics_validation_mse");
    classifier_safe_accuracy_ = StateNumber(state, "classifier_safe_accuracy");
    classifier_unsafe_accuracy_ = StateNumber(state, "classifier_unsafe_accuracy");
    Require(episodes_ >= 0 && total_steps_ >= 0 && pretrain_steps_ >= 0,
            "negative counters (episodes {}, total_steps {}, pretrain_steps {})", episodes_,
            total_steps_, pretrain_steps_);
  });
  transitions_->Load((folder / kTransitionsFile).string());
  labeled_->Load((folder / kLabeledStatesFile).string());
  LoadMpcModels(folder, parts_);
  const fs::path generator_path = folder / kPlannerGeneratorFile;
  torch::Tensor generator;
  try {
    torch::load(generator, generator_path.string());
    parts_.agent->planner().SetGeneratorState(generator);
  } catch (const c10::Error& error) {
    Fail("'{}' is damaged: not a generator state LibTorch can read", generator_path.string());
  }
}

}  // namespace cmbrl

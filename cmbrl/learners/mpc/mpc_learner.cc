#include "cmbrl/learners/mpc/mpc_learner.h"

#include <fmt/format.h>
#include <torch/torch.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/timed.h"
#include "cmbrl/core/torch_util.h"
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
constexpr const char* kRewardModelFile = "reward_model.pt";  // objective.reward: learned only
// objective.termination: learned only
constexpr const char* kTerminationModelFile = "termination_model.pt";
constexpr const char* kPlannerGeneratorFile = "planner_generator.pt";
// Only in a checkpoint taken in the middle of an episode.
constexpr const char* kOpenEpisodeFile = "episode.json";
constexpr const char* kOpenEpisodeEnvFile = "episode_env.bin";
constexpr const char* kPlannerCarriedFile = "planner_carried.pt";

}  // namespace

const std::vector<ProgressColumn<ProgressRow>>& MpcProgressColumns(bool raw_cost) {
  using R = ProgressRow;
  static const std::vector<ProgressColumn<ProgressRow>> columns = {
      {"Epoch", [](const R& r) { return std::to_string(r.epoch); }},
      {"Episode", [](const R& r) { return std::to_string(r.episode); }},
      {kEpRetColumn, [](const R& r) { return ProgressNumber(r.episode_return); }},
      {kEpCostColumn, [](const R& r) { return ProgressNumber(r.episode_cost); }},
      {kTotalEnvInteractsColumn, [](const R& r) { return std::to_string(r.total_env_interacts); }},
      {"PretrainInteracts", [](const R& r) { return std::to_string(r.pretrain_interacts); }},
      {kTimeColumn, [](const R& r) { return ProgressClock(r.time_seconds); }},
      {"DynamicsValMSE", [](const R& r) { return ProgressNumber(r.dynamics_validation_mse); }},
      {"ClassifierSafeAcc", [](const R& r) { return ProgressNumber(r.classifier_safe_accuracy); }},
      {"ClassifierUnsafeAcc",
       [](const R& r) { return ProgressNumber(r.classifier_unsafe_accuracy); }},
      {kFeasibleFractionColumn, [](const R& r) { return ProgressNumber(r.feasible_fraction); }},
      {"MsPerPlan", [](const R& r) { return ProgressClock(r.ms_per_plan); }},
      {kStepsColumn, [](const R& r) { return std::to_string(r.steps); }},
      {"GoalsMet", [](const R& r) { return std::to_string(r.goals_met); }},
      // Added after the columns above: a run begun without them keeps its columns on resume.
      {kHazardStepsColumn, [](const R& r) { return std::to_string(r.hazard_steps); }},
      {kVaseStepsColumn, [](const R& r) { return std::to_string(r.vase_steps); }},
  };
  static const std::vector<ProgressColumn<ProgressRow>> without_raw_cost = FamilyColumns(columns);
  static const std::vector<ProgressColumn<ProgressRow>> with_raw_cost = FamilyColumns(
      columns, ProgressColumn<ProgressRow>{kEpRawCostColumn, [](const R& r) {
                                             return ProgressNumber(r.episode_raw_cost);
                                           }});
  return raw_cost ? with_raw_cost : without_raw_cost;
}

std::string ProgressCsvHeader(bool raw_cost) {
  return ProgressHeader(MpcProgressColumns(raw_cost));
}

std::string ProgressCsvLine(const ProgressRow& row, bool raw_cost) {
  return ProgressLine(MpcProgressColumns(raw_cost), row);
}

void LoadMpcModels(const fs::path& checkpoint, MpcParts& parts) {
  parts.ensemble->Load((checkpoint / kEnsembleFile).string());
  parts.classifier->Load((checkpoint / kClassifierFile).string());
  if (parts.reward_model) parts.reward_model->Load((checkpoint / kRewardModelFile).string());
  if (parts.termination_model) {
    parts.termination_model->Load((checkpoint / kTerminationModelFile).string());
  }
}

MpcLearner::MpcLearner(TrainConfig config, const LearnerInputs& inputs)
    : config_(std::move(config)),
      parts_(AssembleMpc(config_, RunSeeds(config_.seed), inputs)),
      dynamics_validation_mse_(kNaN),
      classifier_safe_accuracy_(kNaN),
      classifier_unsafe_accuracy_(kNaN) {
  const int state_dim = parts_.env->observation_spec().size();
  const int action_dim = parts_.env->action_spec().size();
  const TrainingLoopOptions& t = config_.training;
  raw_cost_column_ = !parts_.env->binary_cost();
  // A learned reward or termination is fitted on what is stored beside the transitions.
  transitions_ = std::make_unique<TransitionBuffer>(state_dim, action_dim, t.transition_capacity,
                                                    parts_.reward_model != nullptr,
                                                    parts_.termination_model != nullptr);
  labeled_ = std::make_unique<LabeledStateBuffer>(state_dim, t.safe_capacity, t.unsafe_capacity);
}

MpcLearner::~MpcLearner() = default;

bool MpcLearner::Finished() const {
  return pretrained_ && !open_ && total_steps_ >= config_.training.total_steps;
}

LearnerStep MpcLearner::Advance(const UnitContext& context) {
  LearnerStep step;
  if (!pretrained_) {
    step.abandoned = Pretrain(context) == FitOutcome::kAbandoned;
    step.summary = {0, total_steps_, budget(), 0.0, 0.0, context.elapsed_seconds()};
    return step;
  }
  // The summary of a unit cut for a checkpoint: no episode ended.
  const auto unfinished = [&](double episode_return, double episode_cost) {
    return ProgressSummary{episodes_ / config_.training.episodes_per_epoch + 1,
                           total_steps_,
                           budget(),
                           episode_return,
                           episode_cost,
                           context.elapsed_seconds()};
  };
  step.models_changed = models_due_;
  if (models_due_) {  // a paused refit, or the run continued past the budget it had stopped at
    const FitOutcome outcome = FitModels(context);
    step.abandoned = outcome == FitOutcome::kAbandoned;
    if (outcome != FitOutcome::kDone) {
      step.summary = unfinished(0.0, 0.0);
      return step;
    }
    models_due_ = false;
  }
  std::optional<ProgressRow> row = Episode(context);
  if (!row) {  // cut for a checkpoint
    step.summary = unfinished(open_->row.episode_return, open_->row.episode_cost);
    return step;
  }
  last_row_ = std::move(*row);
  step.row = ProgressCsvLine(last_row_, raw_cost_column_);
  if (episodes_ % config_.training.episodes_per_epoch == 0) {
    if (Finished()) {
      models_due_ = true;
    } else {
      const FitOutcome outcome = FitModels(context);
      step.abandoned = outcome == FitOutcome::kAbandoned;
      models_due_ = outcome == FitOutcome::kPaused;  // the next Advance goes on with it
      step.models_changed = true;
    }
  }
  step.summary = {last_row_.epoch,          total_steps_,           budget(),
                  last_row_.episode_return, last_row_.episode_cost, last_row_.time_seconds};
  step.summary.episodes = 1;
  step.summary.episodes_cost = last_row_.episode_cost;
  return step;
}

// Facts B6: random actions, each episode cut after pretrain_steps stored transitions.
MpcLearner::FitOutcome MpcLearner::Pretrain(const UnitContext& context) {
  if (!pretrain_collected_) CollectRandomData();
  const FitOutcome outcome = FitModels(context);
  pretrained_ = outcome == FitOutcome::kDone;
  return outcome;
}

void MpcLearner::CollectRandomData() {
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
      const bool kept = transitions_->Add(observation, action, step.observation, step.info.goal_met,
                                          end, step.reward, step.terminated);
      stored += kept;
      AddLabel(step.observation, step.cost, kept);
      observation = std::move(step.observation);
      if (end) break;
    }
  }
  pretrain_collected_ = true;
}

// The classifier's label of a step's next state: only beside a stored transition unless
// label_every_step (facts B4).
void MpcLearner::AddLabel(const std::vector<double>& next_state, double cost,
                          bool transition_kept) {
  if (transition_kept || config_.training.label_every_step) labeled_->Add(next_state, cost > 0.0);
}

std::vector<std::pair<std::string, double>> MpcLearner::TimeSplit() const {
  std::vector<std::pair<std::string, double>> split = {
      {"planning", planning_seconds_},
      {"environment", environment_seconds_},
      {"dynamics_fits", dynamics_fit_seconds_},
      {"classifier_fits", classifier_fit_seconds_}};
  if (parts_.reward_model) split.emplace_back("reward_fits", reward_fit_seconds_);
  if (parts_.termination_model) {
    split.emplace_back("termination_fits", termination_fit_seconds_);
  }
  return split;
}

MpcLearner::FitOutcome MpcLearner::FitModels(const UnitContext& context) {
  // The dynamics fit (half an hour at the paper's sizes) pauses for checkpoints and stops; the
  // classifier's (seconds) is given up on a stop.
  const EnsembleFitReport dynamics = Timed(dynamics_fit_seconds_, [&] {
    return parts_.ensemble->Fit(*transitions_, nullptr, context.checkpoint_due);
  });
  if (dynamics.paused) return FitOutcome::kPaused;
  std::function<bool()> keep_going;
  if (context.stop_requested) keep_going = [&context] { return !context.stop_requested(); };
  const CostFitReport classifier =
      Timed(classifier_fit_seconds_, [&] { return parts_.classifier->Fit(*labeled_, keep_going); });
  if (classifier.interrupted) return FitOutcome::kAbandoned;
  if (parts_.reward_model) {  // seconds at the sizes it is meant for: not pausable
    Timed(reward_fit_seconds_, [&] {
      return parts_.reward_model->Fit(StepInputs(*transitions_), StoredRewards(*transitions_));
    });
  }
  if (parts_.termination_model) {
    Timed(termination_fit_seconds_, [&] {
      return parts_.termination_model->Fit(StepInputs(*transitions_),
                                           StoredTerminations(*transitions_));
    });
  }
  dynamics_validation_mse_ = dynamics.validation_mse;
  classifier_safe_accuracy_ = classifier.safe_accuracy;
  classifier_unsafe_accuracy_ = classifier.unsafe_accuracy;
  return FitOutcome::kDone;
}

std::optional<ProgressRow> MpcLearner::Episode(const UnitContext& context) {
  Env& env = *parts_.env;
  MpcAgent& agent = *parts_.agent;
  if (!open_) {
    OpenEpisode episode;
    episode.observation = config_.training.pretrain_episodes == 0 && episodes_ == 0
                              ? env.Reset(DeriveSeed(config_.seed, kEnvSeedStream))
                              : env.Reset();
    agent.BeginEpisode();
    open_ = std::move(episode);
  }
  OpenEpisode& episode = *open_;
  ProgressRow& row = episode.row;
  for (;;) {
    const std::vector<double> action =
        Timed(planning_seconds_, [&] { return agent.Act(episode.observation); });
    episode.feasible += agent.last_plan().feasible_fraction;
    episode.milliseconds += agent.last_plan().milliseconds;
    StepResult step = Timed(environment_seconds_, [&] { return env.Step(action); });
    const bool end = step.terminated || step.truncated;
    const bool kept = transitions_->Add(episode.observation, action, step.observation,
                                        step.info.goal_met, end, step.reward, step.terminated);
    AddLabel(step.observation, step.cost, kept);
    ++total_steps_;
    ++row.steps;
    row.episode_return += step.reward;
    row.episode_cost += step.cost;
    row.episode_raw_cost += step.info.raw_cost;
    row.goals_met += step.info.goal_met;
    row.hazard_steps += step.info.cost_hazards > 0.0;
    row.vase_steps += step.info.cost_vases_contact > 0.0 || step.info.cost_vases_velocity > 0.0;
    episode.observation = std::move(step.observation);
    if (end) break;
    if (context.checkpoint_due && context.checkpoint_due()) return std::nullopt;
  }
  const double feasible = episode.feasible, milliseconds = episode.milliseconds;
  ProgressRow finished = std::move(row);
  open_.reset();
  return FinishRow(std::move(finished), feasible, milliseconds, context);
}

ProgressRow MpcLearner::FinishRow(ProgressRow row, double feasible, double milliseconds,
                                  const UnitContext& context) {
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
  row.time_seconds = context.elapsed_seconds();
  row.cpu_seconds = context.cpu_seconds();
  return row;
}

void MpcLearner::Save(const fs::path& folder, const fs::path& previous, bool models_changed) const {
  transitions_->Save((folder / kTransitionsFile).string());
  labeled_->Save((folder / kLabeledStatesFile).string());
  if (models_changed || previous.empty() || !fs::exists(previous / kEnsembleFile)) {
    parts_.ensemble->Save((folder / kEnsembleFile).string());
    parts_.classifier->Save((folder / kClassifierFile).string());
    if (parts_.reward_model) parts_.reward_model->Save((folder / kRewardModelFile).string());
    if (parts_.termination_model) {
      parts_.termination_model->Save((folder / kTerminationModelFile).string());
    }
  } else {
    // Unchanged since the last fit: a hard link carries them over without copying (about 50 MB
    // at the paper's sizes).
    std::vector<const char*> names = {kEnsembleFile, kClassifierFile};
    if (parts_.reward_model) names.push_back(kRewardModelFile);
    if (parts_.termination_model) names.push_back(kTerminationModelFile);
    for (const char* name : names) {
      std::error_code linked;
      fs::create_hard_link(previous / name, folder / name, linked);
      if (linked) fs::copy_file(previous / name, folder / name);
    }
  }
  SaveTensor(parts_.agent->planner().GeneratorState(), (folder / kPlannerGeneratorFile).string());
  const nlohmann::json state = {
      {"pretrained", pretrained_},
      {"pretrain_collected", pretrain_collected_},
      {"models_due", models_due_},
      {"episodes", episodes_},
      {"total_steps", total_steps_},
      {"pretrain_steps", pretrain_steps_},
      {"env_generator", parts_.env->GeneratorState()},
      {"dynamics_validation_mse", ProgressNumber(dynamics_validation_mse_)},
      {"classifier_safe_accuracy", ProgressNumber(classifier_safe_accuracy_)},
      {"classifier_unsafe_accuracy", ProgressNumber(classifier_unsafe_accuracy_)},
  };
  WriteLearnerState(folder / kLearnerStateFile, state);
  if (open_) SaveOpenEpisode(folder);
}

void MpcLearner::SaveOpenEpisode(const fs::path& folder) const {
  const ProgressRow& row = open_->row;
  const std::optional<std::string> env_state = parts_.env->TryState();
  nlohmann::json episode = {
      {"observation", open_->observation},    {"steps", row.steps},
      {"episode_return", row.episode_return}, {"episode_cost", row.episode_cost},
      {"goals_met", row.goals_met},           {"hazard_steps", row.hazard_steps},
      {"vase_steps", row.vase_steps},         {"feasible", open_->feasible},
      {"milliseconds", open_->milliseconds},
  };
  if (raw_cost_column_) episode["episode_raw_cost"] = row.episode_raw_cost;
  if (!env_state) episode["env_state_saved"] = false;
  WriteLearnerState(folder / kOpenEpisodeFile, episode);
  if (!env_state) return;  // the episode starts again on resume
  WriteFile(folder / kOpenEpisodeEnvFile, *env_state);
  const torch::Tensor carried = parts_.agent->planner().CarriedState();
  if (carried.defined()) SaveTensor(carried, (folder / kPlannerCarriedFile).string());
}

void MpcLearner::LoadOpenEpisode(const fs::path& folder) {
  OpenEpisode episode;
  const int state_dim = parts_.env->observation_spec().size();
  bool env_state_saved = true;
  ReadLearnerState(folder / kOpenEpisodeFile, [&](const nlohmann::json& json) {
    env_state_saved = json.value("env_state_saved", true);
    episode.observation = json.at("observation").get<std::vector<double>>();
    RequireFiniteRow(episode.observation, state_dim, "the observation");
    ProgressRow& row = episode.row;
    row.steps = json.at("steps").get<int>();
    row.episode_return = json.at("episode_return").get<double>();
    row.episode_cost = json.at("episode_cost").get<double>();
    row.goals_met = json.at("goals_met").get<int>();
    row.hazard_steps = json.at("hazard_steps").get<int>();
    row.vase_steps = json.at("vase_steps").get<int>();
    row.episode_raw_cost = json.value("episode_raw_cost", 0.0);  // absent before it was logged
    episode.feasible = json.at("feasible").get<double>();
    episode.milliseconds = json.at("milliseconds").get<double>();
    Require(row.steps > 0 && row.goals_met >= 0 && row.hazard_steps >= 0 && row.vase_steps >= 0,
            "negative counts or no step (steps {}, goals_met {}, hazard_steps {}, vase_steps {})",
            row.steps, row.goals_met, row.hazard_steps, row.vase_steps);
  });
  if (!env_state_saved) {
    resume_note_ = fmt::format(
        "the episode under way at step {} started again: its environment's state could not be "
        "saved (it does not pickle); its {} steps stay in the data and the budget, with no row",
        total_steps_, episode.row.steps);
    return;
  }
  const fs::path env_path = folder / kOpenEpisodeEnvFile;
  std::ifstream in(env_path, std::ios::binary);
  Require(in.is_open(),
          "'{}' is missing: the checkpoint was taken in the middle of an episode "
          "({}) and needs the environment's state",
          env_path.string(), (folder / kOpenEpisodeFile).string());
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Require(in.good() || in.eof(), "'{}' is damaged: it cannot be read", env_path.string());
  try {
    parts_.env->SetState(bytes);
  } catch (const Error& error) {
    Fail("'{}' is damaged: {}", env_path.string(), error.what());
  }
  const fs::path carried_path = folder / kPlannerCarriedFile;
  torch::Tensor carried;
  if (fs::exists(carried_path)) {
    try {
      torch::load(carried, carried_path.string());
    } catch (const c10::Error&) {
      Fail("'{}' is damaged: not a tensor LibTorch can read", carried_path.string());
    }
  }
  try {
    parts_.agent->planner().SetCarriedState(carried);
  } catch (const Error& error) {
    Fail("'{}' does not fit this run's planner: {}", carried_path.string(), error.what());
  }
  open_ = std::move(episode);
}

void MpcLearner::Load(const fs::path& folder) {
  ReadLearnerState(folder / kLearnerStateFile, [&](const nlohmann::json& state) {
    pretrained_ = state.at("pretrained").get<bool>();
    // Absent before v0.9, whose first checkpoint came after the pre-training's fit.
    pretrain_collected_ = state.value("pretrain_collected", pretrained_);
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
  open_.reset();
  resume_note_.clear();
  if (fs::exists(folder / kOpenEpisodeFile)) LoadOpenEpisode(folder);
}

}  // namespace cmbrl

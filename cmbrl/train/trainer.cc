#include "cmbrl/train/trainer.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/run_lock.h"
#include "cmbrl/core/timed.h"
#include "cmbrl/learners/registry.h"
#include "cmbrl/run/progress_table.h"
#include "cmbrl/run/run_directory.h"
#include "cmbrl/run/run_sessions.h"
#include "cmbrl/train/current_setup.h"

namespace cmbrl {
namespace fs = std::filesystem;

struct Trainer::State {
  TrainConfig config;
  RunDirectory run;
  std::unique_ptr<RunLock> lock;  // held for the trainer's lifetime
  std::unique_ptr<Learner> learner;
  std::int64_t rows = 0;
  // The columns of progress.csv's rows: all the learner's, or the first ones when the run was
  // begun by a version that wrote fewer (ProgressColumnsKept).
  std::optional<size_t> columns_kept;
  double elapsed_before = 0.0;  // seconds of earlier sessions of this run
  double cpu_before = 0.0;      // CPU seconds of earlier sessions of this run
  double session_cpu_start = ProcessCpuSeconds();
  std::vector<std::string> setup_changes;  // against the previous session (run_sessions.h)
  std::chrono::steady_clock::time_point session_start = std::chrono::steady_clock::now();
  double checkpoint_seconds = 0.0;  // this session's checkpoint writes
  int session_episodes = 0;         // the episodes this session's units ended
  double session_cost = 0.0;        // and their cost
  std::int64_t checkpointed_steps = 0;  // what the last checkpoint covers
  bool abandoned = false;  // a unit was given up without a checkpoint: the learner is spent

  State(TrainConfig c, RunDirectory r) : config(std::move(c)), run(std::move(r)) {}

  double Elapsed() const {
    return elapsed_before +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - session_start).count();
  }

  double SessionCpuSeconds() const { return ProcessCpuSeconds() - session_cpu_start; }
  double CpuSeconds() const { return cpu_before + SessionCpuSeconds(); }

  void AppendRow(const std::string& line) {
    AppendToFile(run.progress_file(),
                 (columns_kept ? FirstProgressFields(line, *columns_kept) : line) + "\n");
    ++rows;
  }
};

namespace {

// This session's setup: the machine's and the Python functions the learner was given.
NumericsSetup SessionSetup(const std::string& device, const LearnerInputs& inputs) {
  NumericsSetup setup = CurrentNumericsSetup(device);
  setup.python_functions = inputs.python_functions;
  return setup;
}

}  // namespace

std::unique_ptr<Trainer> Trainer::Start(TrainConfig config, const std::string& run_dir,
                                        const LearnerInputs& given) {
  // A declared Python environment is made here, and its sizes are recorded with the task.
  const LearnerInputs inputs = WithDeclaredPython(config, given);
  RecordPythonEnv(config, inputs);
  ValidateTrainConfig(config, "(command line)");
  RunDirectory(run_dir).RefuseExistingRun();  // before the costly learner is built
  // The learner first: should building it (and taking its memory) fail, nothing is on disk yet.
  auto state = std::make_unique<State>(config, RunDirectory(run_dir));
  state->learner = MakeLearner(config, inputs);
  RunDirectory::Create(run_dir, TrainConfigToYaml(config), state->learner->ProgressHeader(),
                       [&] { state->lock = std::make_unique<RunLock>(run_dir); });
  RecordRunSession(state->run, 0, SessionSetup(config.device, inputs));
  return std::unique_ptr<Trainer>(new Trainer(std::move(state)));
}

std::unique_ptr<Trainer> Trainer::Resume(const std::string& run_dir,
                                         std::optional<std::int64_t> new_budget,
                                         const LearnerInputs& given) {
  RunDirectory run(run_dir);
  Require(run.HoldsRun(), "'{}' holds no run (no {}): start one with --config", run_dir,
          run.config_file().filename().string());
  auto lock = std::make_unique<RunLock>(run_dir);
  RecoverInterruptedCheckpoint(run);  // may put in the config.yaml of an interrupted budget change
  auto state = std::make_unique<State>(LoadTrainConfig(run.config_file().string()), run);
  state->lock = std::move(lock);
  const std::optional<CheckpointManifest> checkpoint = VerifiedCheckpoint(run);
  // Rows written before a first checkpoint that never completed are dropped: the run starts
  // again from its beginning, and its session says so.
  std::string restart_note;
  if (!checkpoint) {
    const std::int64_t uncovered = ProgressRowsInFile(run);
    if (uncovered > 0) {
      restart_note = fmt::format(
          "its first checkpoint was never completed (a full disk, or a stop before it): the run "
          "starts again from its beginning, and the {} row(s) written before it are dropped",
          uncovered);
    }
  }
  const std::int64_t old_budget = state->config.training.total_steps;
  if (new_budget) {
    state->config.training.total_steps = *new_budget;
    ValidateTrainConfig(state->config, run.config_file().string());
  }
  const LearnerInputs inputs = WithDeclaredPython(state->config, given);
  state->learner = MakeLearner(state->config, inputs);
  if (checkpoint) {
    state->learner->Load(run.checkpoint_dir());
    state->rows = checkpoint->rows;
    state->elapsed_before = checkpoint->elapsed_seconds;
    // A checkpoint written before CpuTime was kept belongs to a run whose rows have no CpuTime.
    state->cpu_before = checkpoint->cpu_seconds.value_or(0.0);
    state->checkpointed_steps = state->learner->steps_done();
  }
  if (new_budget && *new_budget != old_budget) {
    const std::int64_t done = state->learner->steps_done();
    // A unit under way at the new budget (an episode, a model-free epoch's value fits) still ends.
    Require(*new_budget > done || (*new_budget == done && !state->learner->Finished()),
            "cannot continue '{}' to {} steps: it has done {} already (its budget was {})", run_dir,
            *new_budget, done, old_budget);
    state->learner->CheckNewBudget(*new_budget);
    ReplaceCheckpointedConfig(run, TrainConfigToYaml(state->config));
  }
  TruncateProgress(run, state->rows);
  std::string header;
  std::ifstream progress(run.progress_file());
  std::getline(progress, header);
  const std::string columns = state->learner->ProgressHeader();
  if (header != columns) {
    state->columns_kept = ProgressColumnsKept(run.progress_file(), header, columns);
  }
  // A finished run asked to go on with nothing to do is no session.
  if (!state->learner->Finished()) {
    std::string note = state->learner->ResumeNote();
    if (!restart_note.empty()) note = note.empty() ? restart_note : restart_note + "; " + note;
    state->setup_changes = RecordRunSession(run, state->learner->steps_done(),
                                            SessionSetup(state->config.device, inputs), note);
  }
  return std::unique_ptr<Trainer>(new Trainer(std::move(state)));
}

Trainer::Trainer(std::unique_ptr<State> state) : state_(std::move(state)) {}
Trainer::~Trainer() = default;

const std::vector<std::string>& Trainer::setup_changes() const { return state_->setup_changes; }
const TrainConfig& Trainer::config() const { return state_->config; }
const Learner& Trainer::learner() const { return *state_->learner; }
std::int64_t Trainer::steps_done() const { return state_->learner->steps_done(); }
std::int64_t Trainer::checkpointed_steps() const { return state_->checkpointed_steps; }

void Trainer::Run(const std::function<void(const ProgressSummary&)>& on_unit) {
  RunOptions options;
  options.on_unit = on_unit;
  Run(options);
}

void Trainer::Run(const RunOptions& options) {
  Require(std::isfinite(options.checkpoint_seconds) && options.checkpoint_seconds >= 0.0,
          "checkpoint_seconds is {}: expected a number of seconds >= 0",
          options.checkpoint_seconds);
  State& s = *state_;
  Require(!s.abandoned,
          "this trainer gave up a unit of work when it was asked to stop: resume the run from its "
          "directory ('{}') instead",
          s.run.root().string());
  using Clock = std::chrono::steady_clock;
  Clock::time_point last_checkpoint = Clock::now();
  bool stop = false;
  UnitContext context;
  context.elapsed_seconds = [&s] { return s.Elapsed(); };
  context.cpu_seconds = [&s] { return s.CpuSeconds(); };
  context.stop_requested = [&] {
    stop = stop || (options.stop_requested && options.stop_requested());
    return stop;
  };
  context.checkpoint_due = [&] {
    return context.stop_requested() ||
           std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >=
               options.checkpoint_seconds;
  };
  while (!s.learner->Finished() && !stop) {
    const LearnerStep step = s.learner->Advance(context);
    if (step.abandoned) {
      s.abandoned = true;
      return;
    }
    if (step.row) {
      s.AppendRow(*step.row);
      s.session_episodes += step.summary.episodes;
      s.session_cost += step.summary.episodes_cost;
    }
    if (step.row && options.on_unit) options.on_unit(step.summary);
    context.stop_requested();  // asked once more: a stop during the unit's end ends the run here
    const auto start = Clock::now();
    WriteCheckpoint(
        s.run, s.rows, s.Elapsed(),
        [&](const fs::path& folder, const fs::path& previous) {
          s.learner->Save(folder, previous, step.models_changed);
        },
        s.learner->steps_done(), s.CpuSeconds());
    s.checkpointed_steps = s.learner->steps_done();
    last_checkpoint = Clock::now();
    s.checkpoint_seconds += std::chrono::duration<double>(last_checkpoint - start).count();
  }
}

std::vector<std::pair<std::string, double>> Trainer::TimeSplit() const {
  const State& s = *state_;
  std::vector<std::pair<std::string, double>> split = s.learner->TimeSplit();
  split.emplace_back("checkpoints", s.checkpoint_seconds);
  double accounted = 0.0;
  for (const auto& part : split) accounted += part.second;
  const double session =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - s.session_start).count();
  split.emplace_back("other", std::max(0.0, session - accounted));
  return split;
}

double Trainer::CpuSecondsThisSession() const { return state_->SessionCpuSeconds(); }

SessionSummary Trainer::ThisSession() const {
  return {state_->session_episodes, state_->session_cost, TimeSplit(), CpuSecondsThisSession()};
}

}  // namespace cmbrl

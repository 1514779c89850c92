// The training loop of the paper (Algorithm 2; facts B6): random-action pre-training, model fits,
// then epochs of MPC episodes each followed by refits, until a budget of agent steps. A run lives
// in one directory and survives being stopped at any moment.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "cmbrl/experiment/config.h"

namespace cmbrl {

// One row of progress.csv: one MPC episode, with the diagnostics of the latest fit and of the
// episode's plans.
struct ProgressRow {
  int epoch = 0;                         // 1-based; refits happen between epochs
  int episode = 0;                       // 1-based MPC episode
  double episode_return = 0.0;           // EpRet
  double episode_cost = 0.0;             // EpCost: agent steps with a violation
  std::int64_t total_env_interacts = 0;  // MPC agent steps so far
  std::int64_t pretrain_interacts = 0;   // random pre-training agent steps (not counted above)
  double time_seconds = 0.0;             // since the run began, across resumes
  double dynamics_validation_mse = 0.0;
  double classifier_safe_accuracy = 0.0;
  double classifier_unsafe_accuracy = 0.0;
  double feasible_fraction = 0.0;  // mean over the episode's plans
  double ms_per_plan = 0.0;        // mean over the episode's plans
  int steps = 0;
  int goals_met = 0;
};

// The CSV header and one line (no newline) of progress.csv.
std::string ProgressCsvHeader();
std::string ProgressCsvLine(const ProgressRow& row);

// Owns the environment, buffers, models and agent of one run. Files in the run directory:
// config.yaml (resolved), progress.csv, checkpoint/ (rewritten after every episode, swapped in
// atomically). Resume truncates progress.csv to the rows the checkpoint covers and continues;
// on the CPU the rows then equal an uninterrupted run's (Time aside). Not thread-safe.
class Trainer {
 public:
  // A new run. Throws cmbrl::Error when run_dir already holds a run.
  static std::unique_ptr<Trainer> Start(const TrainConfig& config, const std::string& run_dir);

  // Continues the run in run_dir from its last checkpoint (or from the start when it stopped
  // before the first one). Throws cmbrl::Error when run_dir holds no run.
  static std::unique_ptr<Trainer> Resume(const std::string& run_dir);

  ~Trainer();

  // Trains until total_steps agent steps. `on_episode` sees each row after it is written to
  // progress.csv and before the checkpoint that covers it.
  void Run(const std::function<void(const ProgressRow&)>& on_episode = {});

  const TrainConfig& config() const;
  std::int64_t total_env_interacts() const;

 private:
  struct State;
  explicit Trainer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace cmbrl

// A training run: one learner (MPC with learned models, the paper's Algorithm 2, or another
// behind run/learner.h) working in one run directory (run/run_directory.h) that survives being
// stopped at any moment. The run owns the lock, progress.csv, checkpoints and resume; the learner
// owns the algorithm.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/learners/registry.h"
#include "cmbrl/run/learner.h"

namespace cmbrl {

// Files in the run directory: config.yaml (resolved), progress.csv, checkpoint/ (rewritten after
// every unit of work and every RunOptions::checkpoint_seconds within one, swapped in atomically,
// with a manifest of what it covers), sessions.jsonl (where each session ran, run_sessions.h).
// Resume checks the checkpoint against its manifest and progress.csv, drops rows written after it
// and continues; on the CPU the rows then equal an uninterrupted run's (Time aside). Not
// thread-safe.
// How one session trains (none of it changes the rows).
struct RunOptions {
  // Sees each unit of work's summary after its row is in progress.csv and before the checkpoint
  // that covers it.
  std::function<void(const ProgressSummary&)> on_unit;
  // A unit of work still going this long after the last checkpoint (an MPC episode at the paper's
  // sizes takes minutes: about 100 agent steps of seconds each; its dynamics fit half an hour)
  // is checkpointed in the middle, between two agent steps or fit epochs, so that an
  // interruption loses at most about this much work. 0: after every step and epoch.
  double checkpoint_seconds = 300.0;
  // Asked after every agent step and every epoch or round of a model fit; true stops the run:
  // at a checkpoint taken at once between two agent steps or dynamics-fit epochs, or, during
  // the classifier's fit, by giving up the unit of work under way without a checkpoint (a
  // resume redoes it from the last one). Run then returns with the learner not finished; after
  // a unit was given up, Run refuses to go on (resume from the directory). For SIGTERM and
  // Ctrl-C.
  std::function<bool()> stop_requested;
};

// What one session (one Start or Resume) did: `cmbrl train`'s closing line, `cmbrl.train`'s
// result.
struct SessionSummary {
  int episodes = 0;   // the episodes its units ended (an MPC unit ends one, an epoch any number)
  double cost = 0.0;  // their summed cost: steps with a violation
  std::vector<std::pair<std::string, double>> seconds;  // TimeSplit
  double cpu_seconds = 0.0;                             // CpuSecondsThisSession
};

class Trainer {
 public:
  // A new run: validates `config` and builds the learner before anything else, and leaves no
  // directory or file behind when that fails. Throws cmbrl::Error when run_dir already holds a
  // run, or another process works in it.
  // `inputs`: what the learner needs beside its config (a Python reward function), completed
  // with what the config's python section declares (WithDeclaredPython); an environment given
  // or declared is recorded as the run's task with its sizes.
  static std::unique_ptr<Trainer> Start(TrainConfig config, const std::string& run_dir,
                                        const LearnerInputs& inputs = {});

  // Continues the run in run_dir from its last checkpoint (or from the start when it stopped
  // before the first one). Throws cmbrl::Error when run_dir holds no run, or its parts disagree
  // (naming the file). With `new_budget`, a run (finished or not) continues to that many steps
  // instead, as if started with that budget, and its config.yaml says so; refused when the run
  // has done that many steps already or its learner cannot (Learner::CheckNewBudget). `inputs`
  // as Start's.
  static std::unique_ptr<Trainer> Resume(const std::string& run_dir,
                                         std::optional<std::int64_t> new_budget = std::nullopt,
                                         const LearnerInputs& inputs = {});

  ~Trainer();

  // Trains until the learner's budget is spent, or until options.stop_requested.
  void Run(const RunOptions& options);
  // The same with the default checkpoint interval.
  void Run(const std::function<void(const ProgressSummary&)>& on_unit = {});

  // How this session's setup differs from the run's previous session (run_sessions.h), one
  // part per field: empty for a new run, an unchanged setup, or a run that kept no sessions.
  // Rows from here on are not those of an uninterrupted run where it is not empty.
  const std::vector<std::string>& setup_changes() const;

  const TrainConfig& config() const;
  const Learner& learner() const;
  std::int64_t steps_done() const;
  // The steps the run's last checkpoint covers (where a resume goes on from): steps_done()
  // unless Run gave up a unit of work when asked to stop.
  std::int64_t checkpointed_steps() const;
  // Where this process's wall time went since Start/Resume: the learner's parts, then
  // "checkpoints" and "other" (the rest of the session, progress rows included), in seconds.
  std::vector<std::pair<std::string, double>> TimeSplit() const;
  // The CPU seconds this process used since Start/Resume (every thread's user and system time):
  // this session's share of the rows' CpuTime.
  double CpuSecondsThisSession() const;
  // All of it at once, with the episodes this session ended and their cost.
  SessionSummary ThisSession() const;

 private:
  struct State;
  explicit Trainer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace cmbrl

// The seam between a run and its training algorithm. A run (train/trainer.h) owns the
// directory, the lock, progress.csv, checkpoints and resume; a learner owns its environment,
// models and counters, and says what its progress rows and checkpoints hold. MPC with learned
// models (the paper's Algorithm 2) is one learner; model-free policy optimisers are others.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace cmbrl {

// What every learner reports after a unit of work, for the live progress line and summaries.
struct ProgressSummary {
  int epoch = 0;
  std::int64_t steps = 0;   // of the budget (agent steps for MPC, environment steps otherwise)
  std::int64_t budget = 0;
  double episode_return = 0.0;  // of the unit's episode(s)
  double episode_cost = 0.0;
  double seconds = 0.0;         // the run's training time when the unit ended
  int episodes = 0;             // the episodes the unit ended
  double episodes_cost = 0.0;   // their summed cost (steps with a violation)
};

// One unit of work done: the progress row it wrote (empty for work without a row, such as the
// random pre-training of Algorithm 2) and whether the learner's large files (its models)
// changed, so that checkpoints can carry unchanged ones over without copying.
struct LearnerStep {
  std::optional<std::string> row;  // a line of progress.csv, no newline
  ProgressSummary summary;
  bool models_changed = true;
  bool abandoned = false;  // see UnitContext::stop_requested: no row, no checkpoint
};

// What the run offers a learner during a unit of work.
struct UnitContext {
  // The run's training time so far (across sessions), for the rows' Time column.
  std::function<double()> elapsed_seconds;
  // The CPU time its sessions have used so far (core/timed.h's ProcessCpuSeconds, across
  // sessions), for the rows' CpuTime column.
  std::function<double()> cpu_seconds;
  // True when the run wants a checkpoint now. A learner whose units are long (MPC episodes) may
  // then stop between two steps and return a step without a row; Save must hold the unit as far
  // as it got, and the next Advance (after Load too) carries it on to the same row.
  std::function<bool()> checkpoint_due;
  // True when the run is asked to stop (a signal, Ctrl-C in Python). A learner in work that
  // cannot be cut at a checkpoint (the classifier's fit) may then abandon the unit: it returns a
  // step with `abandoned`, the run stops without a checkpoint, and a resume redoes the unit from
  // the last one. The learner is not used again.
  std::function<bool()> stop_requested;
};

// Not thread-safe.
class Learner {
 public:
  virtual ~Learner() = default;

  // The header of its progress.csv (no newline).
  virtual std::string ProgressHeader() const = 0;

  // Whether its budget is spent (never in the middle of a unit).
  virtual bool Finished() const = 0;

  // Does the next unit of work, or the next part of one (UnitContext::checkpoint_due).
  virtual LearnerStep Advance(const UnitContext& context) = 0;

  // Writes everything it needs to continue into the empty folder `folder`; may hard-link files
  // of `previous` (the last checkpoint, or an empty path) that did not change.
  virtual void Save(const std::filesystem::path& folder, const std::filesystem::path& previous,
                    bool models_changed) const = 0;

  // Continues from a folder that Save wrote; throws cmbrl::Error naming a damaged file.
  virtual void Load(const std::filesystem::path& folder) = 0;

  // What the last Load could not carry on exactly, in a sentence for the session's record ("" for
  // nothing): e.g. an episode under way that starts again because its environment's state was
  // not saved.
  virtual std::string ResumeNote() const { return {}; }

  // Throws cmbrl::Error when a resumed run may not continue to `new_budget` steps with the rows
  // an uninterrupted run of that budget would have written (for example because the old budget
  // cut its last unit of work short). The trainer has checked new_budget > steps_done().
  virtual void CheckNewBudget(std::int64_t new_budget) const { (void)new_budget; }

  // Steps of the budget done so far, and the budget.
  virtual std::int64_t steps_done() const = 0;
  virtual std::int64_t budget() const = 0;

  // Wall seconds this process spent in each of its parts (e.g. planning, the environment, model
  // fits), in a fixed order; empty where a learner does not keep them.
  virtual std::vector<std::pair<std::string, double>> TimeSplit() const { return {}; }
};

}  // namespace cmbrl

// The training loop of the paper (Algorithm 2; facts B6) as a learner: random-action
// pre-training, model fits, then epochs of MPC episodes, each epoch followed by refits, until a
// budget of agent steps. The refit due after the episode that spends the budget would act in no
// episode: it waits until the run is continued to a larger budget (Trainer::Resume), which then
// gives the rows of a run started with that budget. A finished run's checkpoint therefore holds
// the models its last episodes acted with.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/learners/mpc/mpc_parts.h"
#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/transition_buffer.h"
#include "cmbrl/run/learner.h"
#include "cmbrl/run/progress_columns.h"
#include "cmbrl/run/progress_table.h"

namespace cmbrl {

// One row of an MPC run's progress.csv: one MPC episode, with the diagnostics of the latest fit
// and of the episode's plans.
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
  // Agent steps of the episode that violated a constraint by entering a hazard, and by touching
  // or moving a constrained vase. A step can do both, so their sum can exceed EpCost.
  int hazard_steps = 0;
  int vase_steps = 0;
  // The environment's own costs summed (EpRawCost), where they need not be 0 or 1.
  double episode_raw_cost = 0.0;
  double cpu_seconds = 0.0;  // CpuTime: the run's CPU seconds, across resumes
};

// The columns of an MPC run's progress.csv, the one definition of their names and formats;
// `raw_cost`: with EpRawCost before CpuTime, the last, for an environment whose costs need not
// be 0 or 1.
const std::vector<ProgressColumn<ProgressRow>>& MpcProgressColumns(bool raw_cost = false);

// The CSV header and one line (no newline) of progress.csv.
std::string ProgressCsvHeader(bool raw_cost = false);
std::string ProgressCsvLine(const ProgressRow& row, bool raw_cost = false);

// Loads the models of an MPC checkpoint folder into `parts` (for evaluation). Throws
// cmbrl::Error naming a missing or damaged file.
void LoadMpcModels(const std::filesystem::path& checkpoint, MpcParts& parts);

// Algorithm 2. A unit of work is one MPC episode (or the random pre-training), cut between agent
// steps when the run asks for a checkpoint (UnitContext::checkpoint_due). Checkpoint files:
// transitions.bin, labeled_states.bin, ensemble.pt, classifier.json, planner_generator.pt and
// state.json (counters, the environment's generator, the last fits' figures); in the middle of
// an episode also episode.json (its observation and sums so far), episode_env.bin (the
// environment's state) and planner_carried.pt (the warm-start mean, when there is one). On the
// CPU a resumed run writes the rows an uninterrupted one would (Time aside). An environment whose
// state cannot be saved (Env::TryState) gets no episode_env.bin: its open episode then starts
// again on resume (its steps stay in the data and the budget, with no row), and the session's
// record says so. Not thread-safe.
class MpcLearner final : public Learner {
 public:
  // Builds everything for a validated `config`; throws cmbrl::Error for settings the components
  // refuse.
  // `inputs`: the Python reward and termination of a run whose objective names them.
  explicit MpcLearner(TrainConfig config, const LearnerInputs& inputs = {});
  ~MpcLearner() override;

  std::string ProgressHeader() const override { return ProgressCsvHeader(raw_cost_column_); }
  bool Finished() const override;
  LearnerStep Advance(const UnitContext& context) override;
  // planning, environment, dynamics_fits, classifier_fits, and reward_fits for a learned reward.
  std::vector<std::pair<std::string, double>> TimeSplit() const override;
  void Save(const std::filesystem::path& folder, const std::filesystem::path& previous,
            bool models_changed) const override;
  void Load(const std::filesystem::path& folder) override;
  std::string ResumeNote() const override { return resume_note_; }
  std::int64_t steps_done() const override { return total_steps_; }
  std::int64_t budget() const override { return config_.training.total_steps; }

  const TrainConfig& config() const { return config_; }
  // The last MPC episode's full row (for callers that want more than the summary).
  const ProgressRow& last_row() const { return last_row_; }

 private:
  enum class FitOutcome { kDone, kPaused, kAbandoned };
  // The random pre-training: its data once, then the first fit.
  FitOutcome Pretrain(const UnitContext& context);
  void CollectRandomData();
  // Fits the dynamics, then the classifier. kPaused: the dynamics fit is open for a checkpoint
  // (context.checkpoint_due), and the next call goes on with it. kAbandoned: a stop gave up the
  // classifier's fit (the learner is then not to be saved).
  FitOutcome FitModels(const UnitContext& context);
  void AddLabel(const std::vector<double>& next_state, double cost, bool transition_kept);
  // Carries the episode under way (or a new one) on until it ends, giving its row, or until
  // context.checkpoint_due(), giving nothing.
  std::optional<ProgressRow> Episode(const UnitContext& context);
  // The episode's row once it ended: counters, the fits' figures, means over its plans.
  ProgressRow FinishRow(ProgressRow row, double feasible, double milliseconds,
                        const UnitContext& context);
  void SaveOpenEpisode(const std::filesystem::path& folder) const;
  void LoadOpenEpisode(const std::filesystem::path& folder);

  TrainConfig config_;
  MpcParts parts_;
  std::unique_ptr<TransitionBuffer> transitions_;
  std::unique_ptr<LabeledStateBuffer> labeled_;

  // Counters and the last fits' figures, all in the checkpoint.
  bool pretrained_ = false;
  bool pretrain_collected_ = false;  // its random data is in the buffers
  bool models_due_ = false;  // a refit paused for a checkpoint, or one the budget's end put off
  int episodes_ = 0;
  bool raw_cost_column_ = false;  // EpRawCost: the environment's costs need not be 0 or 1
  // Wall seconds of this process, per part (TimeSplit).
  double planning_seconds_ = 0.0, environment_seconds_ = 0.0, dynamics_fit_seconds_ = 0.0,
         classifier_fit_seconds_ = 0.0, reward_fit_seconds_ = 0.0,
         termination_fit_seconds_ = 0.0;
  std::int64_t total_steps_ = 0;
  std::int64_t pretrain_steps_ = 0;
  double dynamics_validation_mse_;
  double classifier_safe_accuracy_;
  double classifier_unsafe_accuracy_;
  ProgressRow last_row_;

  // An episode cut by a checkpoint: where it stands and its sums so far (in the checkpoint).
  struct OpenEpisode {
    std::vector<double> observation;
    ProgressRow row;  // steps and the sums over them
    double feasible = 0.0;
    double milliseconds = 0.0;
  };
  std::optional<OpenEpisode> open_;
  std::string resume_note_;  // ResumeNote: an open episode that Load could not carry on
};

}  // namespace cmbrl

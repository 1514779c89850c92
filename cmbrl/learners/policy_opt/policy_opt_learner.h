// The model-free baselines of the paper (Section V-B; TRPO, TRPO-Lagrangian, CPO as
// safety-starter-agents ran them, and its PPO and PPO-Lagrangian) as a learner: epochs of steps_per_epoch environment steps with
// the current Gaussian policy, then the penalty, policy and value-function updates.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cmbrl/agent/policy.h"
#include "cmbrl/config/config.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/vector_env.h"
#include "cmbrl/learners/learner_inputs.h"
#include "cmbrl/policy_opt/lagrange.h"
#include "cmbrl/policy_opt/networks.h"
#include "cmbrl/policy_opt/policy_update.h"
#include "cmbrl/run/learner.h"
#include "cmbrl/run/progress_table.h"

namespace cmbrl {

// One row of a model-free run's progress.csv: one epoch, with the original's column names.
struct EpochRow {
  int epoch = 0;                     // 1-based
  double average_episode_return = 0.0;  // AverageEpRet over the epoch's finished episodes
  double average_episode_cost = 0.0;    // AverageEpCost
  double average_episode_length = 0.0;  // EpLen (environment steps)
  int episodes = 0;                  // finished in the epoch
  double cumulative_cost = 0.0;      // every step's cost since the run began
  // Their raw costs (CumulativeRawCost, only for an env whose costs need not be 0 or 1).
  double cumulative_raw_cost = 0.0;
  double cost_rate = 0.0;            // cumulative_cost / TotalEnvInteracts
  double penalty = 0.0;  // TRPO-L's lambda before the epoch's update, CPO's nu, 0 for TRPO
  double kl = 0.0;                   // after the policy update
  int backtrack_iterations = 0;
  int optim_case = -1;               // CPO's, -1 otherwise
  double loss_pi = 0.0;
  double surrogate_cost = 0.0;
  double loss_v = 0.0;
  double loss_vc = 0.0;
  double entropy = 0.0;
  std::int64_t total_env_interacts = 0;
  double time_seconds = 0.0;
  double cpu_seconds = 0.0;  // CpuTime: the run's CPU seconds, across resumes
};

// `raw_cost`: with CumulativeRawCost before CpuTime, the last, for an environment whose costs
// need not be 0 or 1.
const std::vector<ProgressColumn<EpochRow>>& PolicyOptProgressColumns(bool raw_cost = false);

// A trained Gaussian policy acting with its mean, clipped to the action box (for evaluation:
// the environment would clip it too). Not thread-safe.
class GaussianMeanPolicy final : public Policy {
 public:
  // Borrows `policy`, which must outlive this.
  GaussianMeanPolicy(const GaussianPolicy& policy, BoxSpec action_spec);
  // Owns `policy`.
  GaussianMeanPolicy(std::unique_ptr<GaussianPolicy> policy, BoxSpec action_spec);
  ~GaussianMeanPolicy() override;
  std::vector<double> Act(const std::vector<double>& observation) override;

 private:
  std::unique_ptr<GaussianPolicy> owned_;
  const GaussianPolicy& policy_;
  BoxSpec action_spec_;
};

// The policy of a model-free run's checkpoint (`checkpoint_dir`, written by PolicyOptLearner),
// acting with its mean in environments of `observation_dim` and `action_spec`: reads the policy's
// parameters alone, building neither the learner's environments nor its value functions and
// optimisers. Throws cmbrl::Error when the file is missing or holds networks of other shapes.
std::unique_ptr<GaussianMeanPolicy> LoadPolicyOptMeanPolicy(const TrainConfig& config,
                                                            const std::filesystem::path& checkpoint_dir,
                                                            int observation_dim,
                                                            const BoxSpec& action_spec);

// A unit is one epoch. When the run asks for a checkpoint (UnitContext::checkpoint_due, a stop
// included) it pauses after the rollout's round or the value fits' iteration under way, so that
// a stop waits for no more than one of those or the policy update (seconds at the paper's sizes),
// and the next Advance, after Load too, carries the epoch on to the same row. Checkpoint files:
// networks.pt (policy, value functions, the optimisers' moments, the sampler's generator),
// state.json (counters, the penalty, the environments' generators) and, for an epoch under way,
// epoch.json and epoch.pt (its rollout so far with the environments' states, or the value fits'
// data and progress). Not thread-safe.
class PolicyOptLearner final : public Learner {
 public:
  // `config.algorithm` is trpo, trpo-lagrangian or cpo; the environment is config's task and
  // variant (paper-lidar for the paper's runs). Throws cmbrl::Error for a bad configuration.
  explicit PolicyOptLearner(TrainConfig config, const LearnerInputs& inputs = {});
  ~PolicyOptLearner() override;

  std::string ProgressHeader() const override;
  bool Finished() const override;
  LearnerStep Advance(const UnitContext& context) override;
  void Save(const std::filesystem::path& folder, const std::filesystem::path& previous,
            bool models_changed) const override;
  void Load(const std::filesystem::path& folder) override;
  // Refuses when the last epoch was cut short by the old budget: a longer run has a whole epoch
  // there.
  void CheckNewBudget(std::int64_t new_budget) const override;
  // Environment steps taken, those of an epoch's rollout under way included.
  std::int64_t steps_done() const override;
  std::int64_t budget() const override { return config_.training.total_steps; }

  const EpochRow& last_row() const { return last_row_; }
  // Wall seconds of the last epoch's parts in this process (for benchmarks).
  struct Timings {
    double rollout = 0.0;        // environment steps with the networks' forwards
    double policy_update = 0.0;  // penalty and trust-region step
    double value_fits = 0.0;     // both value functions' iterations
  };
  const Timings& last_timings() const { return timings_; }
  // This process's seconds in the rollouts (with the advantages), the penalty and policy updates
  // and the value fits.
  std::vector<std::pair<std::string, double>> TimeSplit() const override;
  // Floating-point operations of one epoch's value fits (forward and backward, both networks).
  double ValueFitFlops(std::int64_t samples) const;
  const GaussianPolicy& policy() const { return *policy_; }

 private:
  struct Epoch;
  struct OpenEpoch;
  // Each environment's share of the open epoch's steps.
  std::vector<std::int64_t> Quota() const;
  void BeginEpoch();
  // Resets the environments marked in `mask` (with `seeds`, if any) into the open epoch's traces.
  void TakeFirstObservations(const std::vector<std::uint8_t>& mask,
                             const std::vector<std::uint64_t>& seeds);
  // The rollout's rounds, until its end (true) or a checkpoint due after a round (false).
  bool Roll(const UnitContext& context);
  // The rolled-out epoch as a batch with its advantages and value targets.
  Epoch Gather();
  // The penalty and policy updates; fills the open epoch's row but for the value losses.
  void Update(Epoch& epoch);
  // Both value functions' iterations, side by side, until their end (true) or a checkpoint due
  // after one (false).
  bool FitValues(const UnitContext& context);
  LearnerStep Unfinished(const UnitContext& context) const;
  void SaveOpenEpoch(const std::filesystem::path& folder) const;
  void LoadOpenEpoch(const std::filesystem::path& folder);
  std::vector<std::string> EnvGenerators() const;

  TrainConfig config_;
  ConstraintHandling handling_;
  std::unique_ptr<VectorEnv> envs_;  // autoreset disabled: every epoch starts new episodes
  at::Generator generator_;  // initialisation, then action sampling
  std::unique_ptr<GaussianPolicy> policy_;
  std::unique_ptr<TanhMlp> value_, cost_value_;
  std::unique_ptr<torch::optim::Adam> policy_optimizer_;  // PPO's (unused by the others)
  std::unique_ptr<torch::optim::Adam> value_optimizer_, cost_value_optimizer_;
  LagrangeMultiplier lagrange_;

  int epochs_ = 0;
  std::int64_t total_steps_ = 0;
  double cumulative_cost_ = 0.0;
  double cumulative_raw_cost_ = 0.0;
  bool raw_cost_column_ = false;  // CumulativeRawCost: the env's costs need not be 0 or 1
  std::unique_ptr<OpenEpoch> open_;  // the epoch under way, between two Advance calls
  EpochRow last_row_;
  Timings timings_, totals_;
};

}  // namespace cmbrl

#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

#include <algorithm>
#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/timed.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/learners/policy_opt/open_epoch.h"
#include "cmbrl/policy_opt/advantages.h"
#include "cmbrl/run/algorithms.h"
#include "cmbrl/run/learner_state.h"
#include "cmbrl/run/progress_columns.h"

namespace cmbrl {
namespace {

// The constraint rule of a model-free algorithm (run/algorithms.h) as the update applies it.
ConstraintHandling HandlingOf(const std::string& algorithm) {
  const AlgorithmEntry& entry = FindAlgorithm(algorithm);
  Require(entry.family == &PolicyOptFamily(), "algorithm '{}' is not a model-free one", algorithm);
  switch (entry.constraint) {
    case ConstraintRule::kNone:
      return ConstraintHandling::kNone;
    case ConstraintRule::kLagrangian:
      return ConstraintHandling::kLagrangian;
    case ConstraintRule::kCpo:
      return ConstraintHandling::kCpo;
  }
  return ConstraintHandling::kNone;
}

bool IsFirstOrder(const std::string& algorithm) { return FindAlgorithm(algorithm).first_order; }

double MeanOf(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double x : values) sum += x;
  return values.empty() ? std::nan("") : sum / static_cast<double>(values.size());
}

torch::Tensor Row(const std::vector<double>& values) {
  return torch::tensor(values, torch::kDouble).to(torch::kFloat).view({1, -1});
}

// GAE advantages and value targets of every path of the epoch, the environments in order
// (`quota` rows each in `values`), of the reward or (`of_cost`) the cost: each path's values,
// then the value of the state it bootstraps from (`bootstrap_values` from the environment's
// `bootstrap_offsets` on), or 0 after a terminal state.
PathTargets EpochGae(const std::vector<EnvTrace>& traces, const std::vector<std::int64_t>& quota,
                     const std::vector<double>& values, const std::vector<double>& bootstrap_values,
                     const std::vector<std::int64_t>& bootstrap_offsets, bool of_cost, double gamma,
                     double lambda) {
  PathTargets all;
  std::int64_t offset = 0;  // the environment's first row in the batch
  for (size_t k = 0; k < traces.size(); ++k) {
    const EnvTrace& trace = traces[k];
    const std::vector<double>& signal = of_cost ? trace.costs : trace.rewards;
    std::int64_t start = 0;
    for (size_t p = 0; p < trace.path_ends.size(); ++p) {
      const std::int64_t end = trace.path_ends[p];
      const std::int64_t row = trace.bootstrap_rows[p];
      std::vector<double> path_values(values.begin() + offset + start,
                                      values.begin() + offset + end);
      path_values.push_back(row < 0 ? 0.0 : bootstrap_values[bootstrap_offsets[k] + row]);
      const PathTargets path =
          GaeTargets(std::vector<double>(signal.begin() + start, signal.begin() + end), path_values,
                     gamma, lambda);
      all.advantages.insert(all.advantages.end(), path.advantages.begin(), path.advantages.end());
      all.returns.insert(all.returns.end(), path.returns.begin(), path.returns.end());
      start = end;
    }
    offset += quota[k];
  }
  return all;
}

}  // namespace

const std::vector<ProgressColumn<EpochRow>>& PolicyOptProgressColumns(bool raw_cost) {
  using R = EpochRow;
  static const std::vector<ProgressColumn<EpochRow>> columns = {
      {"Epoch", [](const R& r) { return std::to_string(r.epoch); }},
      {kAverageEpRetColumn, [](const R& r) { return ProgressNumber(r.average_episode_return); }},
      {kAverageEpCostColumn, [](const R& r) { return ProgressNumber(r.average_episode_cost); }},
      {"EpLen", [](const R& r) { return ProgressNumber(r.average_episode_length); }},
      {"Episodes", [](const R& r) { return std::to_string(r.episodes); }},
      {kCumulativeCostColumn, [](const R& r) { return ProgressNumber(r.cumulative_cost); }},
      {"CostRate", [](const R& r) { return ProgressNumber(r.cost_rate); }},
      {"Penalty", [](const R& r) { return ProgressNumber(r.penalty); }},
      {"KL", [](const R& r) { return ProgressNumber(r.kl); }},
      {"BacktrackIters", [](const R& r) { return std::to_string(r.backtrack_iterations); }},
      {"OptimCase", [](const R& r) { return std::to_string(r.optim_case); }},
      {"LossPi", [](const R& r) { return ProgressNumber(r.loss_pi); }},
      {"SurrCost", [](const R& r) { return ProgressNumber(r.surrogate_cost); }},
      {"LossV", [](const R& r) { return ProgressNumber(r.loss_v); }},
      {"LossVC", [](const R& r) { return ProgressNumber(r.loss_vc); }},
      {"Entropy", [](const R& r) { return ProgressNumber(r.entropy); }},
      {kTotalEnvInteractsColumn, [](const R& r) { return std::to_string(r.total_env_interacts); }},
      {kTimeColumn, [](const R& r) { return ProgressClock(r.time_seconds); }},
  };
  static const std::vector<ProgressColumn<EpochRow>> without_raw_cost = FamilyColumns(columns);
  static const std::vector<ProgressColumn<EpochRow>> with_raw_cost = FamilyColumns(
      columns, ProgressColumn<EpochRow>{kCumulativeRawCostColumn, [](const R& r) {
                                          return ProgressNumber(r.cumulative_raw_cost);
                                        }});
  return raw_cost ? with_raw_cost : without_raw_cost;
}

GaussianMeanPolicy::GaussianMeanPolicy(const GaussianPolicy& policy, BoxSpec action_spec)
    : policy_(policy), action_spec_(std::move(action_spec)) {}

GaussianMeanPolicy::GaussianMeanPolicy(std::unique_ptr<GaussianPolicy> policy, BoxSpec action_spec)
    : owned_(std::move(policy)), policy_(*owned_), action_spec_(std::move(action_spec)) {}

GaussianMeanPolicy::~GaussianMeanPolicy() = default;

std::vector<double> GaussianMeanPolicy::Act(const std::vector<double>& observation) {
  RequireFinite(observation, "observation");
  const torch::NoGradGuard no_grad;
  std::vector<double> action = ToDoubles(policy_.Mean(Row(observation)));
  for (size_t i = 0; i < action.size(); ++i) {
    action[i] = std::clamp(action[i], action_spec_.low[i], action_spec_.high[i]);
  }
  return action;
}

// One epoch's data once rolled out, and the episodes it finished.
struct PolicyOptLearner::Epoch {
  PolicyBatch batch;
  torch::Tensor returns, cost_returns;  // (N) value-function targets
  std::vector<double> episode_returns;  // of the episodes it finished
  double step_cost = 0.0;               // every step's cost, finished episodes or not
  double step_raw_cost = 0.0;           // their raw costs
};

PolicyOptLearner::PolicyOptLearner(TrainConfig config, const LearnerInputs& inputs)
    : config_(std::move(config)),
      handling_(HandlingOf(config_.algorithm)),

      generator_(MakeCpuGenerator(DeriveSeed(config_.seed, kPlannerSeedStream))),
      lagrange_(LagrangeOptions{config_.policy_optimisation.penalty_init,
                                config_.policy_optimisation.penalty_learning_rate}) {
  ValidatePolicyOptimisationOptions(config_.policy_optimisation);
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  std::vector<std::unique_ptr<Env>> envs;
  for (int k = 0; k < o.envs; ++k) {
    envs.push_back(MakeRunEnv(config_, inputs));
  }
  // Stepped on their own threads, which sleep at once after each round: the policy's forward
  // pass runs between rounds, and spinning threads would only take its cores.
  envs_ = std::make_unique<VectorEnv>(std::move(envs), std::min(CoreCount(), o.env_threads),
                                      std::chrono::microseconds(0), Autoreset::kDisabled);
  raw_cost_column_ = !envs_->env(0).binary_cost();
  const int observation_dim = envs_->env(0).observation_spec().size();
  const int action_dim = envs_->env(0).action_spec().size();
  policy_ = std::make_unique<GaussianPolicy>(observation_dim, action_dim, o.policy_hidden,
                                             o.initial_log_std, generator_);
  value_ = std::make_unique<TanhMlp>(observation_dim, o.value_hidden, 1, generator_);
  cost_value_ = std::make_unique<TanhMlp>(observation_dim, o.value_hidden, 1, generator_);
  policy_optimizer_ = std::make_unique<torch::optim::Adam>(
      policy_->parameters(), torch::optim::AdamOptions(o.policy_learning_rate));
  value_optimizer_ = std::make_unique<torch::optim::Adam>(
      value_->parameters(), torch::optim::AdamOptions(o.value_learning_rate));
  cost_value_optimizer_ = std::make_unique<torch::optim::Adam>(
      cost_value_->parameters(), torch::optim::AdamOptions(o.value_learning_rate));
}

PolicyOptLearner::~PolicyOptLearner() = default;

std::string PolicyOptLearner::ProgressHeader() const {
  return cmbrl::ProgressHeader(PolicyOptProgressColumns(raw_cost_column_));
}

bool PolicyOptLearner::Finished() const {
  return !open_ && total_steps_ >= config_.training.total_steps;
}

std::int64_t PolicyOptLearner::steps_done() const {
  if (!open_ || open_->updated) return total_steps_;
  std::int64_t taken = 0;
  for (const EnvTrace& trace : open_->traces)
    taken += static_cast<std::int64_t>(trace.rewards.size());
  return total_steps_ + taken;
}

void PolicyOptLearner::CheckNewBudget(std::int64_t new_budget) const {
  const std::int64_t epoch_steps = config_.policy_optimisation.steps_per_epoch;
  // The steps at the end of the epoch under way (or of the last one), as the old budget cut it.
  std::int64_t reached = total_steps_;
  if (open_ && !open_->updated) reached += open_->steps;
  Require(reached % epoch_steps == 0,
          "cannot continue to {} steps: the run's last epoch was cut to {} of its {} steps by the "
          "old budget, where a run of {} steps has a whole epoch",
          new_budget, reached % epoch_steps, epoch_steps, new_budget);
}

std::vector<std::int64_t> PolicyOptLearner::Quota() const {
  const std::int64_t epoch_steps = open_->steps;
  // A last, shorter epoch is shared out as evenly as it goes.
  const std::int64_t env_count = envs_->size();
  std::vector<std::int64_t> quota(env_count, epoch_steps / env_count);
  for (std::int64_t k = 0; k < epoch_steps % env_count; ++k) ++quota[k];
  return quota;
}

void PolicyOptLearner::TakeFirstObservations(const std::vector<std::uint8_t>& mask,
                                             const std::vector<std::uint64_t>& seeds) {
  const std::vector<double> first = envs_->ResetWhere(mask, seeds);
  const std::int64_t width = envs_->env(0).observation_spec().size();
  for (int k = 0; k < envs_->size(); ++k) {
    if (mask[k] == 0) continue;
    open_->traces[k].observation.assign(first.begin() + k * width, first.begin() + (k + 1) * width);
  }
}

void PolicyOptLearner::BeginEpoch() {
  const int env_count = envs_->size();
  open_ = std::make_unique<OpenEpoch>();
  open_->before = totals_;
  open_->steps = std::min<std::int64_t>(config_.policy_optimisation.steps_per_epoch,
                                        config_.training.total_steps - total_steps_);
  open_->traces.resize(env_count);
  // Every epoch starts new episodes. Environment 0 continues the single-environment seed stream;
  // the others have their own.
  std::vector<std::uint64_t> seeds;
  if (epochs_ == 0) {
    for (int k = 0; k < env_count; ++k) {
      seeds.push_back(DeriveSeed(config_.seed, kEnvSeedStream + 100 * k));
    }
  }
  TakeFirstObservations(std::vector<std::uint8_t>(env_count, 1), seeds);
}

bool PolicyOptLearner::OpenEpoch::RecordStep(int k, std::int64_t t, std::int64_t quota,
                                             const float* observation, const float* action,
                                             const VectorStep& step, std::int64_t observation_dim,
                                             std::int64_t action_dim) {
  EnvTrace& trace = traces[k];
  trace.observations.insert(trace.observations.end(), observation, observation + observation_dim);
  trace.actions.insert(trace.actions.end(), action, action + action_dim);
  trace.rewards.push_back(step.rewards[k]);
  trace.costs.push_back(step.costs[k]);
  trace.episode_return += step.rewards[k];
  trace.episode_cost += step.costs[k];
  step_cost += step.costs[k];
  step_raw_cost += step.raw_costs[k];
  trace.observation.assign(step.observations.begin() + k * observation_dim,
                           step.observations.begin() + (k + 1) * observation_dim);
  const bool terminated = step.terminated[k] != 0;
  const bool terminal = terminated || step.truncated[k] != 0;
  if (!terminal && t != quota - 1) return false;
  trace.path_ends.push_back(t + 1);
  // A time limit or the epoch's end bootstraps from the value of the state reached.
  if (terminated) {
    trace.bootstrap_rows.push_back(-1);
  } else {
    trace.bootstrap_rows.push_back(
        static_cast<std::int64_t>(trace.bootstrap_observations.size() / observation_dim));
    trace.bootstrap_observations.insert(trace.bootstrap_observations.end(),
                                        trace.observation.begin(), trace.observation.end());
  }
  if (terminal) {
    const std::int64_t start =
        trace.path_ends.size() > 1 ? trace.path_ends[trace.path_ends.size() - 2] : 0;
    episode_returns.push_back(trace.episode_return);
    episode_costs.push_back(trace.episode_cost);
    episode_lengths.push_back(static_cast<double>(t + 1 - start));
  }
  trace.episode_return = trace.episode_cost = 0.0;
  return terminal && t + 1 < quota;
}

bool PolicyOptLearner::Roll(const UnitContext& context) {
  OpenEpoch& e = *open_;
  VectorEnv& envs = *envs_;
  const int env_count = envs.size();
  const std::int64_t observation_dim = envs.env(0).observation_spec().size();
  const std::int64_t action_dim = envs.env(0).action_spec().size();
  const std::vector<std::int64_t> quota = Quota();
  const torch::NoGradGuard no_grad;
  // Per round only the actions need the networks (one batched policy forward); the values and
  // log-probabilities follow in one pass over the epoch's rows (Gather).
  const std::int64_t longest = *std::max_element(quota.begin(), quota.end());
  std::vector<std::uint8_t> active(env_count), reset(env_count);
  std::vector<int> stepping;
  std::vector<float> round_observations;
  std::vector<double> step_actions(env_count * action_dim, 0.0);
  while (e.rounds < longest) {
    const std::int64_t t = e.rounds;
    // The environments still stepping this round, their observations in one batch.
    stepping.clear();
    round_observations.clear();
    for (int k = 0; k < env_count; ++k) {
      active[k] = t < quota[k];
      if (active[k] == 0) continue;
      stepping.push_back(k);
      round_observations.insert(round_observations.end(), e.traces[k].observation.begin(),
                                e.traces[k].observation.end());
    }
    const torch::Tensor sampled =
        policy_->Sample(Rows(round_observations, observation_dim), generator_).contiguous();
    const float* action_rows = sampled.data_ptr<float>();
    for (size_t i = 0; i < stepping.size(); ++i) {
      std::copy(action_rows + i * action_dim, action_rows + (i + 1) * action_dim,
                step_actions.begin() + stepping[i] * action_dim);
    }
    const VectorStep step = envs.Step(step_actions, active);
    std::fill(reset.begin(), reset.end(), 0);
    for (size_t i = 0; i < stepping.size(); ++i) {
      const int k = stepping[i];
      reset[k] = e.RecordStep(k, t, quota[k], round_observations.data() + i * observation_dim,
                              action_rows + i * action_dim, step, observation_dim, action_dim);
    }
    if (std::find(reset.begin(), reset.end(), 1) != reset.end()) TakeFirstObservations(reset, {});
    ++e.rounds;
    if (e.rounds < longest && context.checkpoint_due && context.checkpoint_due()) return false;
  }
  return true;
}

PolicyOptLearner::Epoch PolicyOptLearner::Gather() {
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  OpenEpoch& e = *open_;
  const std::int64_t observation_dim = envs_->env(0).observation_spec().size();
  const std::int64_t action_dim = envs_->env(0).action_spec().size();
  const std::vector<std::int64_t> quota = Quota();
  const torch::NoGradGuard no_grad;
  Epoch epoch;
  // The batch in environment order, each environment's steps in time order; the values of its
  // states and of the states the paths bootstrap from, each in one forward pass.
  std::vector<float> observations, actions, bootstrap_observations;
  std::vector<std::int64_t> bootstrap_offsets;  // each environment's first bootstrap row
  for (const EnvTrace& trace : e.traces) {
    observations.insert(observations.end(), trace.observations.begin(), trace.observations.end());
    actions.insert(actions.end(), trace.actions.begin(), trace.actions.end());
    bootstrap_offsets.push_back(
        static_cast<std::int64_t>(bootstrap_observations.size() / observation_dim));
    bootstrap_observations.insert(bootstrap_observations.end(),
                                  trace.bootstrap_observations.begin(),
                                  trace.bootstrap_observations.end());
  }
  PolicyBatch& b = epoch.batch;
  b.observations = Rows(observations, observation_dim);
  b.actions = Rows(actions, action_dim);
  b.log_probs = policy_->LogProb(b.observations, b.actions);
  const auto values_of = [](const TanhMlp& value, const torch::Tensor& rows) {
    if (rows.size(0) == 0) return std::vector<double>();
    return ToDoubles(value.Forward(rows).squeeze(-1));
  };
  const torch::Tensor bootstrap_batch = Rows(bootstrap_observations, observation_dim);
  const std::vector<double> values = values_of(*value_, b.observations);
  const std::vector<double> cost_values = values_of(*cost_value_, b.observations);
  const std::vector<double> bootstrap_values = values_of(*value_, bootstrap_batch);
  const std::vector<double> bootstrap_cost_values = values_of(*cost_value_, bootstrap_batch);
  // GAE over each path, for the reward and for the cost.
  const auto targets = [&](bool of_cost) {
    return EpochGae(e.traces, quota, of_cost ? cost_values : values,
                    of_cost ? bootstrap_cost_values : bootstrap_values, bootstrap_offsets, of_cost,
                    o.gamma, o.lambda);
  };
  PathTargets reward = targets(false), cost = targets(true);
  NormaliseAdvantages(reward.advantages, /*scale=*/true);
  NormaliseAdvantages(cost.advantages, /*scale=*/false);
  b.advantages = torch::tensor(reward.advantages, torch::kDouble).to(torch::kFloat);
  b.cost_advantages = torch::tensor(cost.advantages, torch::kDouble).to(torch::kFloat);
  epoch.returns = torch::tensor(reward.returns, torch::kDouble).to(torch::kFloat);
  epoch.cost_returns = torch::tensor(cost.returns, torch::kDouble).to(torch::kFloat);
  b.episode_cost = MeanOf(e.episode_costs);
  b.episode_length = MeanOf(e.episode_lengths);
  epoch.episode_returns = std::move(e.episode_returns);
  epoch.step_cost = e.step_cost;
  epoch.step_raw_cost = e.step_raw_cost;
  total_steps_ += e.steps;
  e.traces.clear();
  return epoch;
}

void PolicyOptLearner::Update(Epoch& epoch) {
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  OpenEpoch& e = *open_;
  ++epochs_;
  cumulative_cost_ += epoch.step_cost;
  cumulative_raw_cost_ += epoch.step_raw_cost;
  EpochRow& row = e.row;
  row = EpochRow();
  row.epoch = epochs_;
  row.episodes = static_cast<int>(epoch.episode_returns.size());
  row.average_episode_return = MeanOf(epoch.episode_returns);
  row.average_episode_cost = epoch.batch.episode_cost;
  row.average_episode_length = epoch.batch.episode_length;
  // Without a finished episode the constraint has no measurement: it counts as met.
  if (!std::isfinite(epoch.batch.episode_cost)) {
    epoch.batch.episode_cost = o.cost_limit;
    epoch.batch.episode_length = static_cast<double>(epoch.batch.actions.size(0));
  }
  // The original logs the penalty measured before this epoch's update (its Penalty column).
  const double penalty_before = lagrange_.penalty();
  if (handling_ == ConstraintHandling::kLagrangian) {
    lagrange_.Update(epoch.batch.episode_cost, o.cost_limit);
  }
  TrustRegionOptions trust;
  trust.target_kl = o.target_kl;
  trust.damping = o.damping;
  trust.cg_iterations = o.cg_iterations;
  trust.backtrack_coefficient = o.backtrack_coefficient;
  trust.backtrack_iterations = o.backtrack_iterations;
  trust.cost_limit = o.cost_limit;
  PpoOptions ppo;
  ppo.clip_ratio = o.clip_ratio;
  ppo.iterations = o.policy_iterations;
  ppo.kl_margin = o.kl_margin;
  ppo.target_kl = o.target_kl;
  const PolicyUpdateReport update =
      IsFirstOrder(config_.algorithm)
          ? PpoUpdate(*policy_, *policy_optimizer_, epoch.batch,
                      handling_ == ConstraintHandling::kLagrangian, lagrange_.penalty(), ppo)
          : TrustRegionUpdate(*policy_, epoch.batch, handling_, lagrange_.penalty(), trust);
  row.kl = update.kl;
  row.backtrack_iterations = update.backtrack_iterations;
  row.optim_case = update.optim_case;
  row.loss_pi = update.loss_before;
  row.surrogate_cost = update.surrogate_cost_before;
  row.penalty = handling_ == ConstraintHandling::kLagrangian ? penalty_before
                : handling_ == ConstraintHandling::kCpo      ? update.cpo_nu
                                                             : 0.0;
  row.entropy = policy_->Entropy();
  row.cumulative_cost = cumulative_cost_;
  row.cumulative_raw_cost = cumulative_raw_cost_;
  row.total_env_interacts = total_steps_;
  row.cost_rate = cumulative_cost_ / static_cast<double>(total_steps_);
  e.observations = epoch.batch.observations;
  e.returns = epoch.returns;
  e.cost_returns = epoch.cost_returns;
  e.updated = true;
}

bool PolicyOptLearner::FitValues(const UnitContext& context) {
  OpenEpoch& e = *open_;
  const int iterations = config_.policy_optimisation.value_iterations;
  // The two value functions are independent: each is fitted on one thread (Advance's math is
  // single-threaded), side by side where the process has two cores (the fits were 1.4x faster
  // on 2 threads than on 1; two fits at once are nearly 2x). One iteration at a time, the same
  // arithmetic as all at once: each refills the gradients, and Adam keeps its moments.
  while (e.fitted < iterations) {
    double losses[2] = {0.0, 0.0};
    ParallelRanges(2, std::min(2, CoreCount()), [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t i = begin; i < end; ++i) {
        losses[i] = i == 0
                        ? FitValueFunction(*value_, *value_optimizer_, e.observations, e.returns, 1)
                        : FitValueFunction(*cost_value_, *cost_value_optimizer_, e.observations,
                                           e.cost_returns, 1);
      }
    });
    if (e.fitted == 0) {  // the losses before the first step
      e.row.loss_v = losses[0];
      e.row.loss_vc = losses[1];
    }
    ++e.fitted;
    if (e.fitted < iterations && context.checkpoint_due && context.checkpoint_due()) return false;
  }
  return true;
}

LearnerStep PolicyOptLearner::Unfinished(const UnitContext& context) const {
  LearnerStep step;
  step.models_changed = open_->updated;
  step.summary = {epochs_ + (open_->updated ? 0 : 1), steps_done(), budget(), 0.0, 0.0,
                  context.elapsed_seconds()};
  return step;
}

LearnerStep PolicyOptLearner::Advance(const UnitContext& context) {
  // LibTorch and OpenBLAS on one thread for the whole epoch, so that its numbers do not depend
  // on the cores: split over threads, LibTorch's sums (the advantages' statistics, the policy
  // update's losses and Fisher-vector products) add in another order, and a run on 2 cores
  // parted from a run on 1 in its first epoch's KL. The environments still step on their own
  // threads (env_threads), and the two value fits run side by side.
  const ScopedSingleThreadedMath single_threaded;
  if (!open_) BeginEpoch();
  OpenEpoch& e = *open_;
  if (!e.updated) {
    if (!Timed(totals_.rollout, [&] { return Roll(context); })) return Unfinished(context);
    Epoch epoch = Timed(totals_.rollout, [&] { return Gather(); });
    Timed(totals_.policy_update, [&] { Update(epoch); });
  }
  if (!Timed(totals_.value_fits, [&] { return FitValues(context); })) {
    return Unfinished(context);
  }
  EpochRow& row = e.row;
  row.time_seconds = context.elapsed_seconds();
  row.cpu_seconds = context.cpu_seconds();
  last_row_ = row;
  timings_ = {totals_.rollout - e.before.rollout, totals_.policy_update - e.before.policy_update,
              totals_.value_fits - e.before.value_fits};
  open_.reset();

  LearnerStep step;
  step.row = ProgressLine(PolicyOptProgressColumns(raw_cost_column_), row);
  step.summary = {
      row.epoch,       total_steps_, budget(), row.average_episode_return, row.average_episode_cost,
      row.time_seconds};
  step.summary.episodes = row.episodes;
  // The episodes' costs are counts of violating steps: their sum is the average times their
  // number, rounded back to the count. An epoch that ended none has no average (NaN).
  step.summary.episodes_cost =
      row.episodes > 0 ? std::round(row.average_episode_cost * row.episodes) : 0.0;
  return step;
}

double PolicyOptLearner::ValueFitFlops(std::int64_t samples) const {
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  double macs = 0.0;
  int in = envs_->env(0).observation_spec().size();
  for (const int width : o.value_hidden) {
    macs += static_cast<double>(in) * width;
    in = width;
  }
  macs += in;
  // Forward 2 FLOPs a multiply-add, backward about twice the forward; two networks.
  return 2.0 * 3.0 * 2.0 * macs * static_cast<double>(samples) * o.value_iterations;
}

std::vector<std::pair<std::string, double>> PolicyOptLearner::TimeSplit() const {
  return {{"rollout", totals_.rollout},
          {"policy_updates", totals_.policy_update},
          {"value_fits", totals_.value_fits}};
}

std::vector<std::string> PolicyOptLearner::EnvGenerators() const {
  std::vector<std::string> states;
  for (int k = 0; k < envs_->size(); ++k) states.push_back(envs_->env(k).GeneratorState());
  return states;
}

}  // namespace cmbrl

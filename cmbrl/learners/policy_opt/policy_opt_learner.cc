#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/policy_opt/advantages.h"
#include "cmbrl/run/algorithms.h"
#include "cmbrl/run/learner_state.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

constexpr const char* kNetworksFile = "networks.pt";
constexpr const char* kStateFile = "state.json";

// The constraint rule of a model-free algorithm (run/algorithms.h) as the update applies it.
ConstraintHandling HandlingOf(const std::string& algorithm) {
  const AlgorithmEntry& entry = FindAlgorithm(algorithm);
  Require(entry.family == LearnerFamily::kPolicyOptimisation,
          "algorithm '{}' is not a model-free one", algorithm);
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

void WriteParameters(torch::serialize::OutputArchive& archive, const std::string& prefix,
                     const std::vector<torch::Tensor>& parameters) {
  for (size_t i = 0; i < parameters.size(); ++i) {
    archive.write(fmt::format("{}{}", prefix, i), parameters[i].detach());
  }
}

void ReadParameters(torch::serialize::InputArchive& archive, const std::string& prefix,
                    const std::vector<torch::Tensor>& parameters, const fs::path& file) {
  const torch::NoGradGuard no_grad;
  for (size_t i = 0; i < parameters.size(); ++i) {
    torch::Tensor value;
    Require(archive.try_read(fmt::format("{}{}", prefix, i), value) &&
                value.sizes() == parameters[i].sizes(),
            "'{}' does not hold this run's networks ({}{} missing or of another shape)",
            file.string(), prefix, i);
    parameters[i].copy_(value);
  }
}

// The archive of a checkpoint's networks.pt.
torch::serialize::InputArchive ReadNetworks(const fs::path& file) {
  torch::serialize::InputArchive networks;
  try {
    networks.load_from(file.string());
  } catch (const c10::Error& error) {
    Fail("could not read the networks from '{}': {}", file.string(),
         error.what_without_backtrace());
  }
  return networks;
}

}  // namespace

const std::vector<ProgressColumn<EpochRow>>& PolicyOptProgressColumns() {
  using R = EpochRow;
  static const std::vector<ProgressColumn<EpochRow>> columns = {
      {"Epoch", [](const R& r) { return std::to_string(r.epoch); }},
      {"AverageEpRet", [](const R& r) { return ProgressNumber(r.average_episode_return); }},
      {"AverageEpCost", [](const R& r) { return ProgressNumber(r.average_episode_cost); }},
      {"EpLen", [](const R& r) { return ProgressNumber(r.average_episode_length); }},
      {"Episodes", [](const R& r) { return std::to_string(r.episodes); }},
      {"CumulativeCost", [](const R& r) { return ProgressNumber(r.cumulative_cost); }},
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
      {"TotalEnvInteracts", [](const R& r) { return std::to_string(r.total_env_interacts); }},
      {"Time", [](const R& r) { return fmt::format("{:.3f}", r.time_seconds); }},
  };
  return columns;
}

GaussianMeanPolicy::GaussianMeanPolicy(const GaussianPolicy& policy, BoxSpec action_spec)
    : policy_(policy), action_spec_(std::move(action_spec)) {}

GaussianMeanPolicy::GaussianMeanPolicy(std::unique_ptr<GaussianPolicy> policy,
                                       BoxSpec action_spec)
    : owned_(std::move(policy)), policy_(*owned_), action_spec_(std::move(action_spec)) {}

GaussianMeanPolicy::~GaussianMeanPolicy() = default;

std::vector<double> GaussianMeanPolicy::Act(const std::vector<double>& observation) {
  RequireFinite(observation, "observation");
  const torch::NoGradGuard no_grad;
  const torch::Tensor mean = policy_.Mean(Row(observation)).to(torch::kDouble).contiguous();
  std::vector<double> action(mean.data_ptr<double>(), mean.data_ptr<double>() + mean.numel());
  for (size_t i = 0; i < action.size(); ++i) {
    action[i] = std::clamp(action[i], action_spec_.low[i], action_spec_.high[i]);
  }
  return action;
}

// One epoch's data, and the episodes it finished.
struct PolicyOptLearner::Epoch {
  PolicyBatch batch;
  torch::Tensor returns, cost_returns;  // (N) value-function targets
  std::vector<double> episode_returns, episode_costs, episode_lengths;
  double step_cost = 0.0;  // every step's cost, finished episodes or not
};

PolicyOptLearner::PolicyOptLearner(TrainConfig config)
    : config_(std::move(config)),
      handling_(HandlingOf(config_.algorithm)),

      generator_(MakeCpuGenerator(DeriveSeed(config_.seed, kPlannerSeedStream))),
      lagrange_(LagrangeOptions{config_.policy_optimisation.penalty_init,
                                config_.policy_optimisation.penalty_learning_rate}) {
  ValidatePolicyOptimisationOptions(config_.policy_optimisation);
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  std::vector<std::unique_ptr<Env>> envs;
  for (int k = 0; k < o.envs; ++k) {
    envs.push_back(MakeEnv(config_.task, config_.variant, config_.spawn));
  }
  // Stepped on their own threads, which sleep at once after each round: the policy's forward
  // pass runs between rounds, and spinning threads would only take its cores.
  envs_ = std::make_unique<VectorEnv>(std::move(envs), std::min(CoreCount(), o.env_threads),
                                      std::chrono::microseconds(0), Autoreset::kDisabled);
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
  return cmbrl::ProgressHeader(PolicyOptProgressColumns());
}

void PolicyOptLearner::CheckNewBudget(std::int64_t new_budget) const {
  const std::int64_t epoch_steps = config_.policy_optimisation.steps_per_epoch;
  Require(total_steps_ % epoch_steps == 0,
          "cannot continue to {} steps: the run's last epoch was cut to {} of its {} steps by the "
          "old budget of {}, where a run of {} steps has a whole epoch",
          new_budget, total_steps_ % epoch_steps, epoch_steps, config_.training.total_steps,
          new_budget);
}

bool PolicyOptLearner::Finished() const { return total_steps_ >= config_.training.total_steps; }

namespace {

// One environment's share of an epoch: its steps in order, cut into paths.
struct EnvTrace {
  std::vector<double> observation;          // the current one
  std::vector<float> observations, actions;  // each step's, row after row
  std::vector<double> rewards, costs;
  // Each path's end (one past its last step) and, where it bootstraps (a time limit or the
  // epoch's end, not a terminal state), the row of `bootstrap_observations` it bootstraps from.
  std::vector<std::int64_t> path_ends, bootstrap_rows;
  std::vector<float> bootstrap_observations;
  double episode_return = 0.0, episode_cost = 0.0;
};

// Rows of floats, `width` each, as an (N, width) tensor.
torch::Tensor Rows(const std::vector<float>& values, std::int64_t width) {
  return torch::tensor(values, torch::kFloat).view({-1, width});
}

}  // namespace

PolicyOptLearner::Epoch PolicyOptLearner::Collect() {
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  VectorEnv& envs = *envs_;
  const int env_count = envs.size();
  const std::int64_t observation_dim = envs.env(0).observation_spec().size();
  const std::int64_t action_dim = envs.env(0).action_spec().size();
  const std::int64_t epoch_steps =
      std::min<std::int64_t>(o.steps_per_epoch, config_.training.total_steps - total_steps_);
  // Each environment's steps; a last, shorter epoch is shared out as evenly as it goes.
  std::vector<std::int64_t> quota(env_count, epoch_steps / env_count);
  for (std::int64_t k = 0; k < epoch_steps % env_count; ++k) ++quota[k];
  Epoch epoch;
  std::vector<EnvTrace> traces(env_count);
  // Every epoch starts new episodes. Environment 0 continues the single-environment seed stream;
  // the others have their own.
  std::vector<std::uint64_t> seeds;
  if (epochs_ == 0) {
    for (int k = 0; k < env_count; ++k) {
      seeds.push_back(DeriveSeed(config_.seed, kEnvSeedStream + 100 * k));
    }
  }
  const auto take_first_observations = [&](const std::vector<std::uint8_t>& mask) {
    const std::vector<double> first = envs.ResetWhere(mask, seeds);
    for (int k = 0; k < env_count; ++k) {
      if (mask[k] == 0) continue;
      traces[k].observation.assign(first.begin() + k * observation_dim,
                                   first.begin() + (k + 1) * observation_dim);
    }
  };
  take_first_observations(std::vector<std::uint8_t>(env_count, 1));
  seeds.clear();
  const torch::NoGradGuard no_grad;
  // The rollout: per round only the actions need the networks (one batched policy forward);
  // the values and log-probabilities follow in one pass over the epoch's rows.
  const std::int64_t longest = *std::max_element(quota.begin(), quota.end());
  std::vector<std::uint8_t> active(env_count), reset(env_count);
  std::vector<int> stepping;
  std::vector<float> round_observations;
  std::vector<double> step_actions(env_count * action_dim, 0.0);
  for (std::int64_t t = 0; t < longest; ++t) {
    // The environments still stepping this round, their observations in one batch.
    stepping.clear();
    round_observations.clear();
    for (int k = 0; k < env_count; ++k) {
      active[k] = t < quota[k];
      if (active[k] == 0) continue;
      stepping.push_back(k);
      round_observations.insert(round_observations.end(), traces[k].observation.begin(),
                                traces[k].observation.end());
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
      EnvTrace& trace = traces[k];
      trace.observations.insert(trace.observations.end(),
                                round_observations.begin() + i * observation_dim,
                                round_observations.begin() + (i + 1) * observation_dim);
      trace.actions.insert(trace.actions.end(), action_rows + i * action_dim,
                           action_rows + (i + 1) * action_dim);
      trace.rewards.push_back(step.rewards[k]);
      trace.costs.push_back(step.costs[k]);
      trace.episode_return += step.rewards[k];
      trace.episode_cost += step.costs[k];
      epoch.step_cost += step.costs[k];
      trace.observation.assign(step.observations.begin() + k * observation_dim,
                               step.observations.begin() + (k + 1) * observation_dim);
      const bool terminated = step.terminated[k] != 0;
      const bool terminal = terminated || step.truncated[k] != 0;
      if (terminal || t == quota[k] - 1) {
        trace.path_ends.push_back(t + 1);
        // A time limit or the epoch's end bootstraps from the value of the state reached.
        if (terminated) {
          trace.bootstrap_rows.push_back(-1);
        } else {
          trace.bootstrap_rows.push_back(static_cast<std::int64_t>(
              trace.bootstrap_observations.size() / observation_dim));
          trace.bootstrap_observations.insert(trace.bootstrap_observations.end(),
                                              trace.observation.begin(), trace.observation.end());
        }
        if (terminal) {
          const std::int64_t start = trace.path_ends.size() > 1
                                         ? trace.path_ends[trace.path_ends.size() - 2]
                                         : 0;
          epoch.episode_returns.push_back(trace.episode_return);
          epoch.episode_costs.push_back(trace.episode_cost);
          epoch.episode_lengths.push_back(static_cast<double>(t + 1 - start));
        }
        trace.episode_return = trace.episode_cost = 0.0;
        reset[k] = terminal && t + 1 < quota[k];
      }
    }
    if (std::find(reset.begin(), reset.end(), 1) != reset.end()) take_first_observations(reset);
  }
  // The batch in environment order, each environment's steps in time order; the values of its
  // states and of the states the paths bootstrap from, each in one forward pass.
  std::vector<float> observations, actions, bootstrap_observations;
  std::vector<std::int64_t> bootstrap_offsets;  // each environment's first bootstrap row
  for (const EnvTrace& trace : traces) {
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
    const torch::Tensor v = value.Forward(rows).squeeze(-1).to(torch::kDouble).contiguous();
    return std::vector<double>(v.data_ptr<double>(), v.data_ptr<double>() + v.numel());
  };
  const torch::Tensor bootstrap_batch = Rows(bootstrap_observations, observation_dim);
  const std::vector<double> values = values_of(*value_, b.observations);
  const std::vector<double> cost_values = values_of(*cost_value_, b.observations);
  const std::vector<double> bootstrap_values = values_of(*value_, bootstrap_batch);
  const std::vector<double> bootstrap_cost_values = values_of(*cost_value_, bootstrap_batch);
  // GAE over each path.
  std::vector<double> advantages, cost_advantages, returns, cost_returns;
  const auto append = [](std::vector<double>& to, const std::vector<double>& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  std::int64_t offset = 0;  // the environment's first row in the batch
  for (int k = 0; k < env_count; ++k) {
    const EnvTrace& trace = traces[k];
    std::int64_t start = 0;
    for (size_t p = 0; p < trace.path_ends.size(); ++p) {
      const std::int64_t end = trace.path_ends[p];
      const std::int64_t row = trace.bootstrap_rows[p];
      const std::vector<double> rewards(trace.rewards.begin() + start, trace.rewards.begin() + end);
      const std::vector<double> costs(trace.costs.begin() + start, trace.costs.begin() + end);
      std::vector<double> path_values(values.begin() + offset + start,
                                      values.begin() + offset + end);
      std::vector<double> path_cost_values(cost_values.begin() + offset + start,
                                           cost_values.begin() + offset + end);
      path_values.push_back(row < 0 ? 0.0 : bootstrap_values[bootstrap_offsets[k] + row]);
      path_cost_values.push_back(row < 0 ? 0.0
                                         : bootstrap_cost_values[bootstrap_offsets[k] + row]);
      const PathTargets reward = GaeTargets(rewards, path_values, o.gamma, o.lambda);
      const PathTargets cost = GaeTargets(costs, path_cost_values, o.gamma, o.lambda);
      append(advantages, reward.advantages);
      append(returns, reward.returns);
      append(cost_advantages, cost.advantages);
      append(cost_returns, cost.returns);
      start = end;
    }
    offset += quota[k];
  }
  NormaliseAdvantages(advantages, /*scale=*/true);
  NormaliseAdvantages(cost_advantages, /*scale=*/false);
  b.advantages = torch::tensor(advantages, torch::kDouble).to(torch::kFloat);
  b.cost_advantages = torch::tensor(cost_advantages, torch::kDouble).to(torch::kFloat);
  epoch.returns = torch::tensor(returns, torch::kDouble).to(torch::kFloat);
  epoch.cost_returns = torch::tensor(cost_returns, torch::kDouble).to(torch::kFloat);
  b.episode_cost = MeanOf(epoch.episode_costs);
  b.episode_length = MeanOf(epoch.episode_lengths);
  total_steps_ += epoch_steps;
  return epoch;
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

LearnerStep PolicyOptLearner::Advance(const UnitContext& context) {
  const PolicyOptimisationOptions& o = config_.policy_optimisation;
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  auto start = Clock::now();
  Epoch epoch = Collect();
  timings_.rollout = seconds_since(start);
  start = Clock::now();
  ++epochs_;
  cumulative_cost_ += epoch.step_cost;
  EpochRow& row = last_row_;
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
  timings_.policy_update = seconds_since(start);
  start = Clock::now();
  {
    // The two value functions are independent: each is fitted on one thread, side by side where
    // the process has two cores, so the numbers do not depend on the cores (the fits were 1.4x
    // faster on 2 threads than on 1; two fits at once are nearly 2x).
    const ScopedSingleThreadedMath single_threaded;
    double losses[2] = {0.0, 0.0};
    ParallelRanges(2, std::min(2, CoreCount()), [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t i = begin; i < end; ++i) {
        losses[i] = i == 0 ? FitValueFunction(*value_, *value_optimizer_,
                                              epoch.batch.observations, epoch.returns,
                                              o.value_iterations)
                           : FitValueFunction(*cost_value_, *cost_value_optimizer_,
                                              epoch.batch.observations, epoch.cost_returns,
                                              o.value_iterations);
      }
    });
    row.loss_v = losses[0];
    row.loss_vc = losses[1];
  }
  timings_.value_fits = seconds_since(start);
  row.kl = update.kl;
  row.backtrack_iterations = update.backtrack_iterations;
  row.optim_case = update.optim_case;
  row.loss_pi = update.loss_before;
  row.surrogate_cost = update.surrogate_cost_before;
  row.penalty = handling_ == ConstraintHandling::kLagrangian ? penalty_before
                : handling_ == ConstraintHandling::kCpo       ? update.cpo_nu
                                                              : 0.0;
  row.entropy = policy_->Entropy();
  row.cumulative_cost = cumulative_cost_;
  row.total_env_interacts = total_steps_;
  row.cost_rate = cumulative_cost_ / static_cast<double>(total_steps_);
  row.time_seconds = context.elapsed_seconds();

  LearnerStep step;
  step.row = ProgressLine(PolicyOptProgressColumns(), row);
  step.summary = {row.epoch,
                  total_steps_,
                  budget(),
                  row.average_episode_return,
                  row.average_episode_cost,
                  row.time_seconds};
  return step;
}

std::vector<std::string> PolicyOptLearner::EnvGenerators() const {
  std::vector<std::string> states;
  for (int k = 0; k < envs_->size(); ++k) states.push_back(envs_->env(k).GeneratorState());
  return states;
}

void PolicyOptLearner::Save(const fs::path& folder, const fs::path&, bool) const {
  torch::serialize::OutputArchive networks;
  WriteParameters(networks, "policy", policy_->parameters());
  WriteParameters(networks, "value", value_->parameters());
  WriteParameters(networks, "cost_value", cost_value_->parameters());
  torch::serialize::OutputArchive policy_optimizer, value_optimizer, cost_value_optimizer;
  policy_optimizer_->save(policy_optimizer);
  networks.write("policy_optimizer", policy_optimizer);
  value_optimizer_->save(value_optimizer);
  cost_value_optimizer_->save(cost_value_optimizer);
  networks.write("value_optimizer", value_optimizer);
  networks.write("cost_value_optimizer", cost_value_optimizer);
  networks.write("generator", generator_.get_state());
  SaveArchive(networks, (folder / kNetworksFile).string());
  const LagrangeMultiplier::State penalty = lagrange_.state();
  const nlohmann::json state = {
      {"epochs", epochs_},
      {"total_steps", total_steps_},
      {"cumulative_cost", ProgressNumber(cumulative_cost_)},
      {"env_generators", EnvGenerators()},
      {"penalty_parameter", ProgressNumber(penalty.parameter)},
      {"penalty_first_moment", ProgressNumber(penalty.first_moment)},
      {"penalty_second_moment", ProgressNumber(penalty.second_moment)},
      {"penalty_steps", penalty.steps},
  };
  WriteLearnerState(folder / kStateFile, state);
}

void PolicyOptLearner::Load(const fs::path& folder) {
  ReadLearnerState(folder / kStateFile, [&](const nlohmann::json& state) {
    epochs_ = state.at("epochs").get<int>();
    total_steps_ = state.at("total_steps").get<std::int64_t>();
    cumulative_cost_ = StateNumber(state, "cumulative_cost");
    const std::vector<std::string> generators =
        state.at("env_generators").get<std::vector<std::string>>();
    Require(generators.size() == static_cast<size_t>(envs_->size()),
            "the checkpoint holds {} environment generators, this run steps {} environments",
            generators.size(), envs_->size());
    for (int k = 0; k < envs_->size(); ++k) envs_->env(k).SetGeneratorState(generators[k]);
    LagrangeMultiplier::State penalty;
    penalty.parameter = StateNumber(state, "penalty_parameter");
    penalty.first_moment = StateNumber(state, "penalty_first_moment");
    penalty.second_moment = StateNumber(state, "penalty_second_moment");
    penalty.steps = state.at("penalty_steps").get<long long>();
    lagrange_.set_state(penalty);
  });
  const fs::path file = folder / kNetworksFile;
  torch::serialize::InputArchive networks = ReadNetworks(file);
  ReadParameters(networks, "policy", policy_->parameters(), file);
  ReadParameters(networks, "value", value_->parameters(), file);
  ReadParameters(networks, "cost_value", cost_value_->parameters(), file);
  torch::serialize::InputArchive policy_optimizer, value_optimizer, cost_value_optimizer;
  Require(networks.try_read("policy_optimizer", policy_optimizer) &&
              networks.try_read("value_optimizer", value_optimizer) &&
              networks.try_read("cost_value_optimizer", cost_value_optimizer),
          "'{}' holds no optimiser state", file.string());
  policy_optimizer_->load(policy_optimizer);
  value_optimizer_->load(value_optimizer);
  cost_value_optimizer_->load(cost_value_optimizer);
  torch::Tensor generator;
  Require(networks.try_read("generator", generator), "'{}' holds no generator state",
          file.string());
  generator_.set_state(generator);
}

std::unique_ptr<GaussianMeanPolicy> LoadPolicyOptMeanPolicy(const TrainConfig& config,
                                                            const fs::path& checkpoint_dir,
                                                            int observation_dim,
                                                            const BoxSpec& action_spec) {
  const PolicyOptimisationOptions& o = config.policy_optimisation;
  // The initial weights are overwritten: any generator will do.
  at::Generator generator = MakeCpuGenerator(0);
  auto policy = std::make_unique<GaussianPolicy>(observation_dim, action_spec.size(),
                                                 o.policy_hidden, o.initial_log_std, generator);
  const fs::path file = checkpoint_dir / kNetworksFile;
  torch::serialize::InputArchive networks = ReadNetworks(file);
  ReadParameters(networks, "policy", policy->parameters(), file);
  return std::make_unique<GaussianMeanPolicy>(std::move(policy), action_spec);
}

}  // namespace cmbrl

// What a model-free run's checkpoint holds and how it is read back: the networks, their
// optimisers and the generators (networks.pt), the counters and the penalty (state.json), and an
// epoch under way (epoch.json, epoch.pt). Damaged files are named, never half-read.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/learners/policy_opt/open_epoch.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"
#include "cmbrl/policy_opt/adam_archive.h"
#include "cmbrl/run/learner_state.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

constexpr const char* kNetworksFile = "networks.pt";
constexpr const char* kEpochFile = "epoch.json";       // an epoch under way: its counters
constexpr const char* kEpochTensorsFile = "epoch.pt";  // and its data

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

// The archive of a checkpoint's file (networks.pt, epoch.pt); `what` names its contents.
torch::serialize::InputArchive ReadArchive(const fs::path& file, const char* what) {
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(file.string());
  } catch (const c10::Error& error) {
    Fail("could not read the {} from '{}': {}", what, file.string(),
         error.what_without_backtrace());
  }
  return archive;
}

torch::serialize::InputArchive ReadNetworks(const fs::path& file) {
  return ReadArchive(file, "networks");
}

// The row's figures that a checkpoint taken in the value fits keeps (the rest are counts).
constexpr std::pair<const char*, double EpochRow::*> kRowNumbers[] = {
    {"average_episode_return", &EpochRow::average_episode_return},
    {"average_episode_cost", &EpochRow::average_episode_cost},
    {"average_episode_length", &EpochRow::average_episode_length},
    {"cumulative_cost", &EpochRow::cumulative_cost},
    {"cost_rate", &EpochRow::cost_rate},
    {"penalty", &EpochRow::penalty},
    {"kl", &EpochRow::kl},
    {"loss_pi", &EpochRow::loss_pi},
    {"surrogate_cost", &EpochRow::surrogate_cost},
    {"loss_v", &EpochRow::loss_v},
    {"loss_vc", &EpochRow::loss_vc},
    {"entropy", &EpochRow::entropy},
};

// A vector as a 1-D tensor of its own type (torch::tensor makes doubles floats by default).
template <typename T>
torch::Tensor TensorOf(const std::vector<T>& values) {
  return torch::tensor(torch::ArrayRef<T>(values), c10::CppTypeToScalarType<T>::value);
}

// Reads `name` from epoch.pt as a vector of T, of `count` entries when count >= 0.
template <typename T>
std::vector<T> ReadValues(torch::serialize::InputArchive& archive, const std::string& name,
                          std::int64_t count, const fs::path& file) {
  torch::Tensor tensor;
  Require(archive.try_read(name, tensor) && tensor.dim() == 1 &&
              tensor.scalar_type() == c10::CppTypeToScalarType<T>::value &&
              (count < 0 || tensor.size(0) == count),
          "'{}' is damaged: {} is missing or not {} {} values", file.string(), name,
          count < 0 ? std::string("a row of") : std::to_string(count),
          c10::toString(c10::CppTypeToScalarType<T>::value));
  tensor = tensor.contiguous();
  return std::vector<T>(tensor.data_ptr<T>(), tensor.data_ptr<T>() + tensor.numel());
}

}  // namespace

void PolicyOptLearner::Save(const fs::path& folder, const fs::path&, bool) const {
  torch::serialize::OutputArchive networks;
  WriteParameters(networks, "policy", policy_->parameters());
  WriteParameters(networks, "value", value_->parameters());
  WriteParameters(networks, "cost_value", cost_value_->parameters());
  WriteAdamMoments(networks, "policy_adam", *policy_optimizer_);
  WriteAdamMoments(networks, "value_adam", *value_optimizer_);
  WriteAdamMoments(networks, "cost_value_adam", *cost_value_optimizer_);
  networks.write("generator", generator_.get_state());
  SaveArchive(networks, (folder / kNetworksFile).string());
  const LagrangeMultiplier::State penalty = lagrange_.state();
  nlohmann::json state = {
      {"epochs", epochs_},
      {"total_steps", total_steps_},
      {"cumulative_cost", ProgressNumber(cumulative_cost_)},
      {"env_generators", EnvGenerators()},
      {"penalty_parameter", ProgressNumber(penalty.parameter)},
      {"penalty_first_moment", ProgressNumber(penalty.first_moment)},
      {"penalty_second_moment", ProgressNumber(penalty.second_moment)},
      {"penalty_steps", penalty.steps},
  };
  if (raw_cost_column_) state["cumulative_raw_cost"] = ProgressNumber(cumulative_raw_cost_);
  WriteLearnerState(folder / kLearnerStateFile, state);
  if (open_) SaveOpenEpoch(folder);
}

void PolicyOptLearner::Load(const fs::path& folder) {
  ReadLearnerState(folder / kLearnerStateFile, [&](const nlohmann::json& state) {
    epochs_ = state.at("epochs").get<int>();
    total_steps_ = state.at("total_steps").get<std::int64_t>();
    cumulative_cost_ = StateNumber(state, "cumulative_cost");
    // Absent before raw costs were logged, and for 0/1 costs.
    cumulative_raw_cost_ =
        state.contains("cumulative_raw_cost") ? StateNumber(state, "cumulative_raw_cost") : 0.0;
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
  ReadAdamMoments(networks, "policy_adam", "policy_optimizer", *policy_optimizer_, file.string());
  ReadAdamMoments(networks, "value_adam", "value_optimizer", *value_optimizer_, file.string());
  ReadAdamMoments(networks, "cost_value_adam", "cost_value_optimizer", *cost_value_optimizer_,
                  file.string());
  torch::Tensor generator;
  Require(networks.try_read("generator", generator), "'{}' holds no generator state",
          file.string());
  generator_.set_state(generator);
  open_.reset();
  if (fs::exists(folder / kEpochFile)) LoadOpenEpoch(folder);
}

void PolicyOptLearner::SaveOpenEpoch(const fs::path& folder) const {
  const OpenEpoch& e = *open_;
  torch::serialize::OutputArchive tensors;
  nlohmann::json state = {{"updated", e.updated}};
  if (!e.updated) {
    const VectorEnvState envs = envs_->State();
    std::vector<double> returns, costs;
    for (size_t k = 0; k < e.traces.size(); ++k) {
      const EnvTrace& trace = e.traces[k];
      const auto write = [&](const char* name, const torch::Tensor& tensor) {
        tensors.write(fmt::format("{}{}", name, k), tensor);
      };
      write("observation", TensorOf(trace.observation));
      write("observations", TensorOf(trace.observations));
      write("actions", TensorOf(trace.actions));
      write("rewards", TensorOf(trace.rewards));
      write("costs", TensorOf(trace.costs));
      write("path_ends", TensorOf(trace.path_ends));
      write("bootstrap_rows", TensorOf(trace.bootstrap_rows));
      write("bootstrap_observations", TensorOf(trace.bootstrap_observations));
      write("env_state",
            TensorOf(std::vector<std::uint8_t>(envs.envs[k].begin(), envs.envs[k].end())));
      returns.push_back(trace.episode_return);
      costs.push_back(trace.episode_cost);
    }
    tensors.write("open_episode_returns", TensorOf(returns));
    tensors.write("open_episode_costs", TensorOf(costs));
    tensors.write("episode_returns", TensorOf(e.episode_returns));
    tensors.write("episode_costs", TensorOf(e.episode_costs));
    tensors.write("episode_lengths", TensorOf(e.episode_lengths));
    state["steps"] = e.steps;
    state["rounds"] = e.rounds;
    state["step_cost"] = ProgressNumber(e.step_cost);
    if (raw_cost_column_) state["step_raw_cost"] = ProgressNumber(e.step_raw_cost);
    state["needs_reset"] = envs.needs_reset;
  } else {
    tensors.write("observations", e.observations.reshape({-1}));
    tensors.write("returns", e.returns);
    tensors.write("cost_returns", e.cost_returns);
    state["fitted"] = e.fitted;
    state["epoch"] = e.row.epoch;
    state["episodes"] = e.row.episodes;
    state["backtrack_iterations"] = e.row.backtrack_iterations;
    state["optim_case"] = e.row.optim_case;
    state["total_env_interacts"] = e.row.total_env_interacts;
    for (const auto& [name, field] : kRowNumbers) state[name] = ProgressNumber(e.row.*field);
  }
  SaveArchive(tensors, (folder / kEpochTensorsFile).string());
  WriteLearnerState(folder / kEpochFile, state);
}

namespace {

// Environment k's trace of an open epoch after `rounds` rounds, as SaveOpenEpoch wrote it to
// `file`; throws cmbrl::Error naming a damaged file.
EnvTrace ReadTrace(torch::serialize::InputArchive& tensors, const fs::path& file, int k,
                   std::int64_t rounds, std::int64_t observation_dim, std::int64_t action_dim) {
  EnvTrace trace;
  const auto name = [k](const char* what) { return fmt::format("{}{}", what, k); };
  trace.observation = ReadValues<double>(tensors, name("observation"), observation_dim, file);
  trace.rewards = ReadValues<double>(tensors, name("rewards"), -1, file);
  const auto steps = static_cast<std::int64_t>(trace.rewards.size());
  Require(steps <= rounds, "'{}' is damaged: environment {} took {} steps in {} rounds",
          file.string(), k, steps, rounds);
  trace.costs = ReadValues<double>(tensors, name("costs"), steps, file);
  trace.observations =
      ReadValues<float>(tensors, name("observations"), steps * observation_dim, file);
  trace.actions = ReadValues<float>(tensors, name("actions"), steps * action_dim, file);
  trace.path_ends = ReadValues<std::int64_t>(tensors, name("path_ends"), -1, file);
  trace.bootstrap_rows =
      ReadValues<std::int64_t>(tensors, name("bootstrap_rows"), trace.path_ends.size(), file);
  trace.bootstrap_observations =
      ReadValues<float>(tensors, name("bootstrap_observations"), -1, file);
  Require(trace.bootstrap_observations.size() % observation_dim == 0,
          "'{}' is damaged: environment {}'s bootstrap states are not rows of {}", file.string(), k,
          observation_dim);
  return trace;
}

}  // namespace

void PolicyOptLearner::LoadOpenEpoch(const fs::path& folder) {
  auto e = std::make_unique<OpenEpoch>();
  const int env_count = envs_->size();
  VectorEnvState envs;
  ReadLearnerState(folder / kEpochFile, [&](const nlohmann::json& state) {
    e->updated = state.at("updated").get<bool>();
    if (!e->updated) {
      e->steps = state.at("steps").get<std::int64_t>();
      e->rounds = state.at("rounds").get<std::int64_t>();
      e->step_cost = StateNumber(state, "step_cost");
      e->step_raw_cost =
          state.contains("step_raw_cost") ? StateNumber(state, "step_raw_cost") : 0.0;
      envs.needs_reset = state.at("needs_reset").get<std::vector<std::uint8_t>>();
      const std::int64_t epoch_steps = config_.policy_optimisation.steps_per_epoch;
      const std::int64_t rounds = (e->steps + env_count - 1) / env_count;  // the longest quota
      Require(e->steps > 0 && e->steps <= epoch_steps && e->rounds > 0 && e->rounds < rounds &&
                  envs.needs_reset.size() == static_cast<size_t>(env_count),
              "an epoch of {} steps at round {}, with {} reset flags: expected 1 to {} steps, a "
              "round from 1 to the epoch's last but one, and {} flags",
              e->steps, e->rounds, envs.needs_reset.size(), epoch_steps, env_count);
      return;
    }
    e->fitted = state.at("fitted").get<int>();
    EpochRow& row = e->row;
    row.epoch = state.at("epoch").get<int>();
    row.episodes = state.at("episodes").get<int>();
    row.backtrack_iterations = state.at("backtrack_iterations").get<int>();
    row.optim_case = state.at("optim_case").get<int>();
    row.total_env_interacts = state.at("total_env_interacts").get<std::int64_t>();
    for (const auto& [name, field] : kRowNumbers) row.*field = StateNumber(state, name);
    Require(e->fitted > 0 && e->fitted < config_.policy_optimisation.value_iterations &&
                row.epoch == epochs_ && row.total_env_interacts == total_steps_,
            "value fits at iteration {} of {} in epoch {} after {} steps, where the run has "
            "done {} epochs and {} steps",
            e->fitted, config_.policy_optimisation.value_iterations, row.epoch,
            row.total_env_interacts, epochs_, total_steps_);
  });
  const fs::path file = folder / kEpochTensorsFile;
  torch::serialize::InputArchive tensors = ReadArchive(file, "epoch under way");
  const std::int64_t observation_dim = envs_->env(0).observation_spec().size();
  const std::int64_t action_dim = envs_->env(0).action_spec().size();
  if (e->updated) {
    const std::vector<float> returns = ReadValues<float>(tensors, "returns", -1, file);
    const auto rows = static_cast<std::int64_t>(returns.size());
    e->returns = torch::tensor(returns, torch::kFloat);
    e->cost_returns =
        torch::tensor(ReadValues<float>(tensors, "cost_returns", rows, file), torch::kFloat);
    e->observations = Rows(ReadValues<float>(tensors, "observations", rows * observation_dim, file),
                           observation_dim);
    open_ = std::move(e);
    return;
  }
  e->traces.resize(env_count);
  const std::vector<double> returns =
      ReadValues<double>(tensors, "open_episode_returns", env_count, file);
  const std::vector<double> costs =
      ReadValues<double>(tensors, "open_episode_costs", env_count, file);
  for (int k = 0; k < env_count; ++k) {
    e->traces[k] = ReadTrace(tensors, file, k, e->rounds, observation_dim, action_dim);
    const std::vector<std::uint8_t> bytes =
        ReadValues<std::uint8_t>(tensors, fmt::format("env_state{}", k), -1, file);
    envs.envs.emplace_back(bytes.begin(), bytes.end());
    e->traces[k].episode_return = returns[k];
    e->traces[k].episode_cost = costs[k];
  }
  e->episode_returns = ReadValues<double>(tensors, "episode_returns", -1, file);
  e->episode_costs = ReadValues<double>(tensors, "episode_costs", e->episode_returns.size(), file);
  e->episode_lengths =
      ReadValues<double>(tensors, "episode_lengths", e->episode_returns.size(), file);
  try {
    envs_->SetState(envs);
  } catch (const Error& error) {
    Fail("'{}' is damaged: {}", file.string(), error.what());
  }
  open_ = std::move(e);
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

#include "cmbrl/env/previous_action_env.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"

namespace cmbrl {

namespace {

// A state's bytes (ByteWriter): this tag, A, A doubles, then the wrapped environment's state.
constexpr char kStateTag[] = "cmbrl-previous-action-v1";

}  // namespace

std::string PreviousActionName(int i) { return fmt::format("previous_action_{}", i); }

int PreviousActionOffset(const BoxSpec& observation, int action_dim) {
  const auto first = std::find(observation.names.begin(), observation.names.end(),
                               PreviousActionName(0));
  if (first == observation.names.end()) return -1;
  const int offset = static_cast<int>(first - observation.names.begin());
  for (int i = 0; i < action_dim; ++i) {
    Require(offset + i < observation.size() && observation.names[offset + i] ==
                                                   PreviousActionName(i),
            "the observation's previous action starts at component {} and has no '{}' after "
            "it: expected {} components previous_action_0 to previous_action_{} in a row",
            offset, PreviousActionName(i), action_dim, action_dim - 1);
  }
  return offset;
}

PreviousActionEnv::PreviousActionEnv(std::unique_ptr<Env> env) : env_(std::move(env)) {
  Require(env_ != nullptr, "PreviousActionEnv: no environment to wrap");
  const BoxSpec& actions = env_->action_spec();
  Require(PreviousActionOffset(env_->observation_spec(), actions.size()) < 0,
          "the environment already observes its previous action (previous_action_0 is one of "
          "its components): it is wrapped once");
  observation_spec_ = env_->observation_spec();
  for (int i = 0; i < actions.size(); ++i) {
    observation_spec_.low.push_back(actions.low[i]);
    observation_spec_.high.push_back(actions.high[i]);
    observation_spec_.names.push_back(PreviousActionName(i));
  }
  previous_.assign(actions.size(), 0.0);
}

std::vector<double> PreviousActionEnv::Observed(std::vector<double> observation) const {
  observation.insert(observation.end(), previous_.begin(), previous_.end());
  return observation;
}

std::vector<double> PreviousActionEnv::Reset(std::optional<std::uint64_t> seed) {
  std::vector<double> observation = env_->Reset(seed);
  std::fill(previous_.begin(), previous_.end(), 0.0);
  return Observed(std::move(observation));
}

StepResult PreviousActionEnv::Step(const std::vector<double>& action) {
  StepResult result = env_->Step(action);  // checks the action's size and finiteness
  const BoxSpec& box = env_->action_spec();
  for (int i = 0; i < box.size(); ++i) {
    previous_[i] = std::clamp(action[i], box.low[i], box.high[i]);
  }
  result.observation = Observed(std::move(result.observation));
  return result;
}

std::string PreviousActionEnv::StateWith(const std::string& wrapped_state) const {
  ByteWriter writer;
  writer.Write(std::string(kStateTag));
  writer.Write<std::uint64_t>(previous_.size());
  writer.WriteBytes(previous_.data(), previous_.size() * sizeof(double));
  writer.Write(wrapped_state);
  return writer.Take();
}

std::string PreviousActionEnv::State() const { return StateWith(env_->State()); }

std::optional<std::string> PreviousActionEnv::TryState() const {
  std::optional<std::string> wrapped = env_->TryState();
  if (!wrapped) return std::nullopt;
  return StateWith(*wrapped);
}

void PreviousActionEnv::SetState(const std::string& state) {
  ByteWriter tag;
  tag.Write(std::string(kStateTag));
  const std::string prefix = tag.Take();
  Require(state.compare(0, prefix.size(), prefix) == 0,
          "this state is not an environment's with its previous action (it does not start with "
          "'{}')",
          kStateTag);
  ByteReader reader(std::string_view(state).substr(prefix.size()),
                    "this state of an environment with its previous action");
  const auto count = reader.Read<std::uint64_t>();
  Require(count == previous_.size(),
          "this state holds a previous action of {} components, and this environment takes {} "
          "actions",
          count, previous_.size());
  std::vector<double> previous(previous_.size());
  const std::string_view bytes = reader.ReadBytes(previous.size() * sizeof(double));
  std::memcpy(previous.data(), bytes.data(), bytes.size());
  const std::string wrapped = reader.ReadString();
  reader.ExpectEnd();
  env_->SetState(wrapped);  // throws, changing nothing, for a bad state
  previous_ = std::move(previous);
}

}  // namespace cmbrl

#include "cmbrl/env/previous_action_env.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "cmbrl/core/check.h"

namespace cmbrl {

namespace {

// A state's first bytes: this tag, then A as text and a newline, then A doubles, then the
// wrapped environment's state.
constexpr char kStateTag[] = "cmbrl-previous-action-v1 ";

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
  std::string state = fmt::format("{}{}\n", kStateTag, previous_.size());
  const std::size_t head = state.size();
  state.resize(head + previous_.size() * sizeof(double));
  std::memcpy(state.data() + head, previous_.data(), previous_.size() * sizeof(double));
  return state + wrapped_state;
}

std::string PreviousActionEnv::State() const { return StateWith(env_->State()); }

std::optional<std::string> PreviousActionEnv::TryState() const {
  std::optional<std::string> wrapped = env_->TryState();
  if (!wrapped) return std::nullopt;
  return StateWith(*wrapped);
}

void PreviousActionEnv::SetState(const std::string& state) {
  const std::string tag = kStateTag;
  const std::size_t newline = state.find('\n');
  Require(state.compare(0, tag.size(), tag) == 0 && newline != std::string::npos,
          "this state is not an environment's with its previous action (it does not start with "
          "'{}')",
          tag.substr(0, tag.size() - 1));
  const std::string count = state.substr(tag.size(), newline - tag.size());
  Require(count == std::to_string(previous_.size()),
          "this state holds a previous action of '{}' components, and this environment takes {} "
          "actions",
          count, previous_.size());
  const std::size_t head = newline + 1;
  const std::size_t bytes = previous_.size() * sizeof(double);
  Require(state.size() >= head + bytes,
          "this state ends inside its previous action ({} bytes, expected at least {})",
          state.size(), head + bytes);
  std::vector<double> previous(previous_.size());
  std::memcpy(previous.data(), state.data() + head, bytes);
  env_->SetState(state.substr(head + bytes));  // throws, changing nothing, for a bad state
  previous_ = std::move(previous);
}

}  // namespace cmbrl

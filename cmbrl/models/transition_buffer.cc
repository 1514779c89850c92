#include "cmbrl/models/transition_buffer.h"

#include <algorithm>
#include <cmath>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"

namespace cmbrl {
TransitionBuffer::TransitionBuffer(int state_dim, int action_dim, int capacity, bool keep_rewards,
                                   bool keep_terminations)
    : state_dim_(state_dim),
      action_dim_(action_dim),
      capacity_(capacity),
      keep_rewards_(keep_rewards),
      keep_terminations_(keep_terminations) {
  Require(state_dim > 0, "state_dim is {}: expected a positive number", state_dim);
  Require(action_dim > 0, "action_dim is {}: expected a positive number", action_dim);
  Require(capacity > 0, "capacity is {}: expected a positive number", capacity);
  states_.resize(static_cast<size_t>(capacity) * state_dim);
  actions_.resize(static_cast<size_t>(capacity) * action_dim);
  next_.resize(static_cast<size_t>(capacity) * state_dim);
  if (keep_rewards_) rewards_.resize(static_cast<size_t>(capacity));
  if (keep_terminations_) terminations_.resize(static_cast<size_t>(capacity));
}

bool TransitionBuffer::Add(const std::vector<double>& state, const std::vector<double>& action,
                           const std::vector<double>& next_state, bool goal_met, bool episode_end,
                           double reward, bool terminated) {
  RequireFiniteRow(state, state_dim_, "transition state");
  RequireFiniteRow(action, action_dim_, "transition action");
  RequireFiniteRow(next_state, state_dim_, "transition next state");
  Require(std::isfinite(reward), "the transition's reward is {}: expected a finite number",
          reward);
  const bool kept_end = keep_terminations_ && terminated;
  if (goal_met || (episode_end && !kept_end)) return false;
  const size_t slot = static_cast<size_t>(next_slot_);
  std::copy(state.begin(), state.end(), states_.begin() + slot * state_dim_);
  std::copy(action.begin(), action.end(), actions_.begin() + slot * action_dim_);
  std::copy(next_state.begin(), next_state.end(), next_.begin() + slot * state_dim_);
  if (keep_rewards_) rewards_[slot] = static_cast<float>(reward);
  if (keep_terminations_) terminations_[slot] = terminated ? 1.0F : 0.0F;
  next_slot_ = (next_slot_ + 1) % capacity_;
  size_ = std::min(size_ + 1, capacity_);
  ++total_added_;
  return true;
}

void TransitionBuffer::Save(const std::string& path) const {
  BinaryWriter out(path, "cmbrl-transitions-v1");
  out.Write(state_dim_);
  out.Write(action_dim_);
  out.Write(capacity_);
  out.Write(size_);
  out.Write(next_slot_);
  out.Write(total_added_);
  // Slots fill from 0 up, so the used ones are always the first size_.
  const auto used = [this](const std::vector<float>& rows, int width) {
    return std::vector<float>(rows.begin(), rows.begin() + static_cast<size_t>(size_) * width);
  };
  out.Write(used(states_, state_dim_));
  out.Write(used(actions_, action_dim_));
  out.Write(used(next_, state_dim_));
  if (keep_rewards_) out.Write(used(rewards_, 1));
  if (keep_terminations_) out.Write(used(terminations_, 1));
  out.Close();
}

void TransitionBuffer::Load(const std::string& path) {
  BinaryReader in(path, "cmbrl-transitions-v1");
  const int state_dim = in.Read<int>(), action_dim = in.Read<int>(), capacity = in.Read<int>();
  Require(state_dim == state_dim_ && action_dim == action_dim_ && capacity == capacity_,
          "'{}' holds a ({}, {}) buffer of {} transitions; this one is ({}, {}) of {}", path,
          state_dim, action_dim, capacity, state_dim_, action_dim_, capacity_);
  size_ = in.Read<int>();
  next_slot_ = in.Read<int>();
  total_added_ = in.Read<std::int64_t>();
  Require(size_ >= 0 && size_ <= capacity_ && next_slot_ >= 0 && next_slot_ < capacity_,
          "'{}' is damaged", path);
  const auto restore = [&](std::vector<float>& rows, int width) {
    const std::vector<float> used = in.ReadVector<float>();
    Require(used.size() == static_cast<size_t>(size_) * width, "'{}' is damaged", path);
    std::copy(used.begin(), used.end(), rows.begin());
  };
  restore(states_, state_dim_);
  restore(actions_, action_dim_);
  restore(next_, state_dim_);
  if (keep_rewards_) restore(rewards_, 1);
  if (keep_terminations_) restore(terminations_, 1);
}

}  // namespace cmbrl

// Ring buffer of (state, action, next state) transitions for fitting the dynamics model
// (paper Section IV-A; facts B3).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cmbrl {

// Fixed-capacity ring of transitions stored as float rows; the oldest is overwritten when full.
// Not thread-safe.
class TransitionBuffer {
 public:
  // Throws cmbrl::Error for non-positive sizes. `keep_rewards`: each transition's reward is
  // stored too (for a learned reward, step_model.h); `keep_terminations`: whether it ended the
  // episode by itself (for a learned termination), and such transitions are stored. The file
  // holds what is kept after the rest, rewards first.
  TransitionBuffer(int state_dim, int action_dim, int capacity = 500000,
                   bool keep_rewards = false, bool keep_terminations = false);

  // Stores a transition unless it reached the goal or ended the episode: those jump (the goal
  // is relocated, the episode restarts) and the paper's code leaves them out. A buffer that
  // keeps terminations stores a `terminated` one (its next state is the one the episode ended
  // in, not a jump), marked; `episode_end` is true for it too. Returns whether it was stored.
  // Throws cmbrl::Error for wrong sizes or non-finite values.
  bool Add(const std::vector<double>& state, const std::vector<double>& action,
           const std::vector<double>& next_state, bool goal_met = false, bool episode_end = false,
           double reward = 0.0, bool terminated = false);

  int size() const { return size_; }
  int capacity() const { return capacity_; }
  int state_dim() const { return state_dim_; }
  int action_dim() const { return action_dim_; }
  std::int64_t total_added() const { return total_added_; }  // stored ever, overwritten included

  // Everything, capacity included; Load checks the dimensions and throws cmbrl::Error naming the
  // file on a mismatch or damage.
  void Save(const std::string& path) const;
  void Load(const std::string& path);

  // Row i (0 <= i < size()) of each array; rows are in storage order, not time order.
  const float* states() const { return states_.data(); }     // (size, state_dim)
  const float* actions() const { return actions_.data(); }   // (size, action_dim)
  const float* next_states() const { return next_.data(); }  // (size, state_dim)
  bool keeps_rewards() const { return keep_rewards_; }
  const float* rewards() const { return rewards_.data(); }  // (size); empty unless kept
  bool keeps_terminations() const { return keep_terminations_; }
  const float* terminations() const { return terminations_.data(); }  // (size) of 0 or 1

 private:
  int state_dim_;
  int action_dim_;
  int capacity_;
  int size_ = 0;
  int next_slot_ = 0;
  std::int64_t total_added_ = 0;
  std::vector<float> states_;
  std::vector<float> actions_;
  std::vector<float> next_;
  bool keep_rewards_;
  std::vector<float> rewards_;
  bool keep_terminations_;
  std::vector<float> terminations_;
};

}  // namespace cmbrl

// Safe and unsafe states for fitting the constraint classifier (paper Section IV-A: separate
// buffers keep the classifier from drowning the rare unsafe class; facts B4).
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

// Two rings of states, one per label. Not thread-safe.
class LabeledStateBuffer {
 public:
  // Paper capacities: 50,000 safe and 10,000 unsafe states.
  LabeledStateBuffer(int state_dim, int safe_capacity = 50000, int unsafe_capacity = 10000);

  // Stores a state under its label. Throws cmbrl::Error for a wrong size or non-finite value.
  void Add(const std::vector<double>& state, bool unsafe);

  int safe_size() const { return safe_.size; }
  int unsafe_size() const { return unsafe_.size; }
  int state_dim() const { return state_dim_; }

  // Everything; Load checks the dimension and capacities and throws cmbrl::Error naming the file.
  void Save(const std::string& path) const;
  void Load(const std::string& path);

  // The newest `count` safe states (at most safe_size()), oldest first: (count, state_dim).
  std::vector<float> NewestSafe(int count) const;
  // The safe states of the last `count` used slots in storage order (at most safe_size()): the
  // original's x0[-count:] (facts B4). Before the ring wraps these are the newest, oldest first;
  // after it wraps, the end of the array whatever its age. (count, state_dim).
  std::vector<float> LastSafeSlots(int count) const;
  // Every unsafe state, oldest first: (unsafe_size(), state_dim).
  std::vector<float> AllUnsafe() const;

 private:
  struct Ring {
    std::vector<float> rows;
    int capacity = 0;
    int size = 0;
    int next_slot = 0;
  };
  void Push(Ring& ring, const std::vector<double>& state);
  std::vector<float> Newest(const Ring& ring, int count) const;

  int state_dim_;
  Ring safe_;
  Ring unsafe_;
};

}  // namespace cmbrl

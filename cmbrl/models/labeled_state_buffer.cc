#include "cmbrl/models/labeled_state_buffer.h"

#include <algorithm>
#include <cmath>

#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"

namespace cmbrl {

LabeledStateBuffer::LabeledStateBuffer(int state_dim, int safe_capacity, int unsafe_capacity)
    : state_dim_(state_dim) {
  Require(state_dim > 0, "state_dim is {}: expected a positive number", state_dim);
  Require(safe_capacity > 0, "safe_capacity is {}: expected a positive number", safe_capacity);
  Require(unsafe_capacity > 0, "unsafe_capacity is {}: expected a positive number",
          unsafe_capacity);
  safe_.capacity = safe_capacity;
  safe_.rows.resize(static_cast<size_t>(safe_capacity) * state_dim);
  unsafe_.capacity = unsafe_capacity;
  unsafe_.rows.resize(static_cast<size_t>(unsafe_capacity) * state_dim);
}

void LabeledStateBuffer::Add(const std::vector<double>& state, bool unsafe) {
  RequireFiniteRow(state, state_dim_, "labeled state");
  Push(unsafe ? unsafe_ : safe_, state);
}

void LabeledStateBuffer::Push(Ring& ring, const std::vector<double>& state) {
  std::copy(state.begin(), state.end(),
            ring.rows.begin() + static_cast<size_t>(ring.next_slot) * state_dim_);
  ring.next_slot = (ring.next_slot + 1) % ring.capacity;
  ring.size = std::min(ring.size + 1, ring.capacity);
}

std::vector<float> LabeledStateBuffer::Newest(const Ring& ring, int count) const {
  count = std::clamp(count, 0, ring.size);
  std::vector<float> out(static_cast<size_t>(count) * state_dim_);
  // The newest row sits just before next_slot; walk back `count` rows, write oldest first.
  for (int i = 0; i < count; ++i) {
    const int slot = ((ring.next_slot - count + i) % ring.capacity + ring.capacity) % ring.capacity;
    std::copy_n(ring.rows.begin() + static_cast<size_t>(slot) * state_dim_, state_dim_,
                out.begin() + static_cast<size_t>(i) * state_dim_);
  }
  return out;
}

std::vector<float> LabeledStateBuffer::NewestSafe(int count) const { return Newest(safe_, count); }

std::vector<float> LabeledStateBuffer::LastSafeSlots(int count) const {
  count = std::clamp(count, 0, safe_.size);
  // Used slots are always 0 .. size-1 (they fill from 0 up), so the last `count` are contiguous.
  const auto first = safe_.rows.begin() + static_cast<size_t>(safe_.size - count) * state_dim_;
  return std::vector<float>(first, first + static_cast<size_t>(count) * state_dim_);
}

std::vector<float> LabeledStateBuffer::AllUnsafe() const { return Newest(unsafe_, unsafe_.size); }

void LabeledStateBuffer::Save(const std::string& path) const {
  BinaryWriter out(path, "cmbrl-labeled-states-v1");
  out.Write(state_dim_);
  for (const Ring* ring : {&safe_, &unsafe_}) {
    out.Write(ring->capacity);
    out.Write(ring->size);
    out.Write(ring->next_slot);
    // Slots fill from 0 up, so the used ones are always the first `size`.
    out.Write(std::vector<float>(
        ring->rows.begin(), ring->rows.begin() + static_cast<size_t>(ring->size) * state_dim_));
  }
  out.Close();
}

void LabeledStateBuffer::Load(const std::string& path) {
  BinaryReader in(path, "cmbrl-labeled-states-v1");
  const int state_dim = in.Read<int>();
  Require(state_dim == state_dim_, "'{}' holds states of {} dimensions; this buffer {}", path,
          state_dim, state_dim_);
  for (Ring* ring : {&safe_, &unsafe_}) {
    const int capacity = in.Read<int>();
    Require(capacity == ring->capacity, "'{}' holds a ring of {} states; this one has {}", path,
            capacity, ring->capacity);
    ring->size = in.Read<int>();
    ring->next_slot = in.Read<int>();
    Require(ring->size >= 0 && ring->size <= capacity && ring->next_slot >= 0 &&
                ring->next_slot < capacity,
            "'{}' is damaged", path);
    const std::vector<float> used = in.ReadVector<float>();
    Require(used.size() == static_cast<size_t>(ring->size) * state_dim_, "'{}' is damaged", path);
    std::copy(used.begin(), used.end(), ring->rows.begin());
  }
}

}  // namespace cmbrl

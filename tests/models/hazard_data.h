// Synthetic constraint data shaped like PointGoal1's 24-dim state: hazards at ego-frame XY in
// columns 10..23; a state is unsafe when any hazard lies within 0.2 m of the robot.
#pragma once

#include <cmath>
#include <vector>

#include "cmbrl/core/rng.h"

namespace cmbrl::testing {

constexpr int kHazardStateDim = 24;

inline std::vector<float> HazardState(Rng& rng) {
  std::vector<float> state(kHazardStateDim);
  for (int i = 0; i < 10; ++i) state[i] = static_cast<float>(Uniform(rng, -1, 1));
  for (int i = 10; i < kHazardStateDim; ++i) state[i] = static_cast<float>(Uniform(rng, -2, 2));
  return state;
}

inline bool HazardUnsafe(const std::vector<float>& state) {
  for (int h = 10; h < kHazardStateDim; h += 2) {
    if (std::hypot(state[h], state[h + 1]) < 0.2) return true;
  }
  return false;
}

// Rows drawn until there are `unsafe` unsafe and `safe` safe states (surplus dropped).
struct HazardData {
  std::vector<float> safe, unsafe;  // row-major (count, 24)
  int safe_count = 0, unsafe_count = 0;
};
inline HazardData MakeHazardData(int safe, int unsafe, std::uint64_t seed) {
  HazardData data;
  Rng rng(seed);
  while (data.safe_count < safe || data.unsafe_count < unsafe) {
    const std::vector<float> state = HazardState(rng);
    if (HazardUnsafe(state)) {
      if (data.unsafe_count == unsafe) continue;
      data.unsafe.insert(data.unsafe.end(), state.begin(), state.end());
      ++data.unsafe_count;
    } else {
      if (data.safe_count == safe) continue;
      data.safe.insert(data.safe.end(), state.begin(), state.end());
      ++data.safe_count;
    }
  }
  return data;
}

}  // namespace cmbrl::testing

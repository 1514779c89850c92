// A known nonlinear map for model tests: one step of a damped, driven pendulum.
#pragma once

#include <cmath>

#include "cmbrl/core/rng.h"
#include "cmbrl/models/transition_buffer.h"

namespace cmbrl::testing {

// State (angle, angular velocity), action (torque in [-1, 1]); 0.05 s semi-implicit Euler.
inline std::vector<double> PendulumStep(const std::vector<double>& state, double torque) {
  constexpr double kDt = 0.05, kGravity = 9.81, kDamping = 0.1, kGain = 2.0;
  const double velocity =
      state[1] + kDt * (-kGravity * std::sin(state[0]) - kDamping * state[1] + kGain * torque);
  return {state[0] + kDt * velocity, velocity};
}

// `count` transitions from uniform states in [-pi, pi] x [-4, 4] and torques in [-1, 1].
inline TransitionBuffer PendulumData(int count, std::uint64_t seed) {
  TransitionBuffer buffer(2, 1, count);
  Rng rng(seed);
  for (int i = 0; i < count; ++i) {
    const std::vector<double> state = {Uniform(rng, -M_PI, M_PI), Uniform(rng, -4, 4)};
    const double torque = Uniform(rng, -1, 1);
    buffer.Add(state, {torque}, PendulumStep(state, torque));
  }
  return buffer;
}

}  // namespace cmbrl::testing

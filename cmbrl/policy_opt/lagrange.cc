#include "cmbrl/policy_opt/lagrange.h"

#include <algorithm>
#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

LagrangeMultiplier::LagrangeMultiplier(LagrangeOptions options) : options_(options) {
  Require(options_.initial_penalty > 0 && std::isfinite(options_.initial_penalty),
          "initial_penalty is {}: expected a positive number", options_.initial_penalty);
  Require(options_.learning_rate > 0 && std::isfinite(options_.learning_rate),
          "penalty learning_rate is {}: expected a positive number", options_.learning_rate);
  // The inverse of softplus, so that penalty() starts at initial_penalty (the original clamps
  // the argument of the logarithm at 1e-8).
  parameter_ = std::log(std::max(std::exp(options_.initial_penalty) - 1.0, 1e-8));
}

double LagrangeMultiplier::penalty() const {
  // softplus, written to stay finite for large parameters.
  return parameter_ > 30 ? parameter_ : std::log1p(std::exp(parameter_));
}

void LagrangeMultiplier::Update(double episode_cost, double cost_limit) {
  Require(std::isfinite(episode_cost) && std::isfinite(cost_limit),
          "episode cost {} and cost limit {} must be finite", episode_cost, cost_limit);
  const double gradient = -(episode_cost - cost_limit);  // d/dp of -p (cost - limit)
  ++steps_;
  first_moment_ = options_.beta1 * first_moment_ + (1 - options_.beta1) * gradient;
  second_moment_ = options_.beta2 * second_moment_ + (1 - options_.beta2) * gradient * gradient;
  const double corrected_first = first_moment_ / (1 - std::pow(options_.beta1, steps_));
  const double corrected_second = second_moment_ / (1 - std::pow(options_.beta2, steps_));
  parameter_ -= options_.learning_rate * corrected_first /
                (std::sqrt(corrected_second) + options_.epsilon);
}

void LagrangeMultiplier::set_state(const State& state) {
  Require(std::isfinite(state.parameter) && state.second_moment >= 0 && state.steps >= 0,
          "not a Lagrange multiplier state: parameter {}, second moment {}, steps {}",
          state.parameter, state.second_moment, state.steps);
  parameter_ = state.parameter;
  first_moment_ = state.first_moment;
  second_moment_ = state.second_moment;
  steps_ = state.steps;
}

}  // namespace cmbrl

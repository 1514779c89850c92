#include "cmbrl/policy_opt/policy_opt_options.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

void ValidatePolicyOptimisationOptions(const PolicyOptimisationOptions& o) {
  Require(o.steps_per_epoch >= 1 && o.steps_per_epoch <= 100'000'000,
          "steps_per_epoch is {}: expected 1 to 100000000", o.steps_per_epoch);
  Require(o.envs >= 1 && o.envs <= 1024, "envs is {}: expected 1 to 1024", o.envs);
  Require(o.env_threads >= 1 && o.env_threads <= 1024, "env_threads is {}: expected 1 to 1024",
          o.env_threads);
  Require(o.steps_per_epoch % o.envs == 0,
          "steps_per_epoch is {} and envs {}: expected steps_per_epoch to be a multiple of envs",
          o.steps_per_epoch, o.envs);
  for (const auto* hidden : {&o.policy_hidden, &o.value_hidden}) {
    Require(!hidden->empty() && hidden->size() <= 16,
            "{}: {} hidden layers given, expected 1 to 16",
            hidden == &o.policy_hidden ? "policy_hidden" : "value_hidden", hidden->size());
    for (size_t i = 0; i < hidden->size(); ++i) {
      Require((*hidden)[i] >= 1 && (*hidden)[i] <= 65536, "{}[{}] is {}: expected 1 to 65536",
              hidden == &o.policy_hidden ? "policy_hidden" : "value_hidden", i, (*hidden)[i]);
    }
  }
  Require(std::isfinite(o.initial_log_std) && o.initial_log_std > -20 && o.initial_log_std < 5,
          "initial_log_std is {}: expected a number in (-20, 5)", o.initial_log_std);
  // Upper bounds: values no one means, which train to NaN or never move.
  Require(o.value_learning_rate > 0 && o.value_learning_rate <= 1,
          "value_learning_rate is {}: expected a number in (0, 1]", o.value_learning_rate);
  Require(o.value_iterations >= 0 && o.value_iterations <= 100'000,
          "value_iterations is {}: expected 0 to 100000", o.value_iterations);
  Require(o.gamma >= 0 && o.gamma <= 1, "gamma is {}: expected a number in [0, 1]", o.gamma);
  Require(o.lambda >= 0 && o.lambda <= 1, "lambda is {}: expected a number in [0, 1]", o.lambda);
  Require(o.target_kl > 0 && o.target_kl <= 10, "target_kl is {}: expected a number in (0, 10]",
          o.target_kl);
  Require(o.damping >= 0 && o.damping <= 1000, "damping is {}: expected a number in [0, 1000]",
          o.damping);
  Require(o.cg_iterations >= 1 && o.cg_iterations <= 1000,
          "cg_iterations is {}: expected 1 to 1000", o.cg_iterations);
  Require(o.backtrack_coefficient > 0 && o.backtrack_coefficient < 1,
          "backtrack_coefficient is {}: expected a number in (0, 1)", o.backtrack_coefficient);
  Require(o.backtrack_iterations >= 1 && o.backtrack_iterations <= 1000,
          "backtrack_iterations is {}: expected 1 to 1000", o.backtrack_iterations);
  // An episode's cost counts its violating steps: a limit above 1e9 is no limit, and a
  // multiplier above 1e9 outweighs any float32 advantage.
  Require(o.cost_limit >= 0 && o.cost_limit <= 1e9,
          "cost_limit is {}: expected a number in [0, 1e9]", o.cost_limit);
  Require(o.penalty_init > 0 && o.penalty_init <= 1e9,
          "penalty_init is {}: expected a number in (0, 1e9]", o.penalty_init);
  Require(o.penalty_learning_rate > 0 && o.penalty_learning_rate <= 1,
          "penalty_learning_rate is {}: expected a number in (0, 1]", o.penalty_learning_rate);
  Require(o.policy_learning_rate > 0 && o.policy_learning_rate <= 1,
          "policy_learning_rate is {}: expected a number in (0, 1]", o.policy_learning_rate);
  Require(o.policy_iterations >= 1 && o.policy_iterations <= 100'000,
          "policy_iterations is {}: expected 1 to 100000", o.policy_iterations);
  Require(o.clip_ratio > 0 && o.clip_ratio < 1, "clip_ratio is {}: expected a number in (0, 1)",
          o.clip_ratio);
  // A step is kept while its KL is within kl_margin x target_kl: beyond 100x nothing is kept out.
  Require(o.kl_margin > 0 && o.kl_margin <= 100, "kl_margin is {}: expected a number in (0, 100]",
          o.kl_margin);
}

}  // namespace cmbrl

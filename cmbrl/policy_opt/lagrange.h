// TRPO-Lagrangian's penalty (paper Section V-B's baseline; safety-starter-agents): lambda =
// softplus(p), p learnt by Adam on the loss -p (EpCost - limit), so lambda rises while the
// episodes cost more than the limit and falls while they cost less. The policy objective is
// (A - lambda A_c) / (1 + lambda).
#pragma once

namespace cmbrl {

struct LagrangeOptions {
  double initial_penalty = 1.0;  // lambda before the first update
  double learning_rate = 0.05;   // Adam's
  double beta1 = 0.9;            // Adam's moment decays and epsilon (TensorFlow's defaults)
  double beta2 = 0.999;
  double epsilon = 1e-8;
};

// Not thread-safe. Its state is three numbers and a step count, for checkpoints.
class LagrangeMultiplier {
 public:
  // Throws cmbrl::Error naming a non-positive initial penalty or learning rate.
  explicit LagrangeMultiplier(LagrangeOptions options = {});

  double penalty() const;  // lambda = softplus(p)
  double parameter() const { return parameter_; }

  // One Adam step (bias-corrected, Kingma and Ba) on -p (episode_cost - cost_limit), with the
  // epoch's mean episode cost.
  void Update(double episode_cost, double cost_limit);

  struct State {
    double parameter = 0.0, first_moment = 0.0, second_moment = 0.0;
    long long steps = 0;
  };
  State state() const { return {parameter_, first_moment_, second_moment_, steps_}; }
  void set_state(const State& state);

 private:
  LagrangeOptions options_;
  double parameter_;
  double first_moment_ = 0.0;
  double second_moment_ = 0.0;
  long long steps_ = 0;
};

}  // namespace cmbrl

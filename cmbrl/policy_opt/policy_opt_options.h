// Settings of the model-free baselines, with safety-starter-agents' values as the paper's runs
// used them (their config.json in data/reference/model-free; issue 13's list).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cmbrl {

// The original's EPS, added in every division of the model-free updates that could meet zero
// (not a setting).
constexpr double kPolicyOptEps = 1e-8;

struct PolicyOptimisationOptions {
  std::int64_t steps_per_epoch = 30000;  // environment steps collected between updates
  // Environments stepped side by side, each steps_per_epoch / envs steps an epoch, their
  // observations through one batched policy forward (the original: 1 process, 1 environment).
  // Results depend on the count, never on thread timing.
  int envs = 1;
  // Threads that step the environments of a round (at most envs, and the cores this process
  // has). A thread is started per round, which costs more than it saves on a loaded machine
  // (docs/PERFORMANCE.md); results do not depend on it.
  int env_threads = 1;
  std::vector<int> policy_hidden = {256, 256};
  double initial_log_std = -0.5;
  std::vector<int> value_hidden = {256, 256};  // reward and cost value functions alike
  double value_learning_rate = 1e-3;
  int value_iterations = 80;  // full-batch Adam steps per epoch
  double gamma = 0.99;        // rewards and costs
  double lambda = 0.97;       // GAE, rewards and costs
  double target_kl = 0.01;
  double damping = 0.1;
  int cg_iterations = 10;
  double backtrack_coefficient = 0.8;
  int backtrack_iterations = 10;
  double cost_limit = 10.0;  // per episode (EpCost)
  double penalty_init = 1.0;  // TRPO-Lagrangian's lambda before the first update
  double penalty_learning_rate = 0.05;
  // PPO and PPO-Lagrangian (safety-starter-agents' PPOAgent defaults).
  double policy_learning_rate = 3e-4;
  int policy_iterations = 80;
  double clip_ratio = 0.2;
  double kl_margin = 1.2;
};

// Throws cmbrl::Error naming the first field with a bad value.
void ValidatePolicyOptimisationOptions(const PolicyOptimisationOptions& options);

}  // namespace cmbrl

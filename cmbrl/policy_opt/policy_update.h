// One epoch's updates of the model-free baselines, as safety-starter-agents makes them (paper
// Section V-B): the policy's trust-region step (TRPO: natural gradient with backtracking line
// search under a hard KL limit; TRPO-Lagrangian: the same on (A - lambda A_c) / (1 + lambda);
// CPO: the dual step with its recovery cases and a line search on KL and cost), and the value
// functions' Adam iterations.
#pragma once

#include <torch/torch.h>

#include "cmbrl/policy_opt/networks.h"

namespace cmbrl {

enum class ConstraintHandling {
  kNone,        // TRPO
  kLagrangian,  // TRPO-Lagrangian
  kCpo,         // CPO
};

// An epoch's data, flattened over its episodes.
struct PolicyBatch {
  torch::Tensor observations;     // (N, O)
  torch::Tensor actions;          // (N, A)
  torch::Tensor advantages;       // (N) reward advantages, normalised
  torch::Tensor cost_advantages;  // (N) cost advantages, centred
  torch::Tensor log_probs;        // (N) log pi_old(a | s) at collection
  double episode_cost = 0.0;      // the epoch's mean EpCost
  double episode_length = 0.0;    // the epoch's mean EpLen
};

struct TrustRegionOptions {
  double target_kl = 0.01;
  double damping = 0.1;  // added to the Fisher-vector product
  int cg_iterations = 10;
  double backtrack_coefficient = 0.8;
  int backtrack_iterations = 10;
  double cost_limit = 10.0;  // per episode
  double cpo_margin = 0.0;
};

struct PolicyUpdateReport {
  double loss_before = 0.0;  // the policy loss (negative objective)
  double loss_after = 0.0;
  double surrogate_cost_before = 0.0;
  double surrogate_cost_after = 0.0;
  double kl = 0.0;              // mean KL(old || new) after the update
  int backtrack_iterations = 0; // line-search steps taken (the last one when it failed)
  bool accepted = true;         // false: the line search failed and the old policy was kept
  int optim_case = -1;          // CPO's case (SolveCpoDual), -1 otherwise
  double cpo_nu = 0.0;          // CPO's cost multiplier (the logs' Penalty)
};

// Throws cmbrl::Error for a batch whose tensors disagree in length or a bad option.
PolicyUpdateReport TrustRegionUpdate(GaussianPolicy& policy, const PolicyBatch& batch,
                                     ConstraintHandling handling, double penalty,
                                     const TrustRegionOptions& options);

// PPO's first-order update (safety-starter-agents' PPOAgent): up to `iterations` full-batch
// Adam steps on the clipped surrogate (PPO-Lagrangian: (surr - lambda surr_cost) / (1 +
// lambda)), stopping once the mean KL from the epoch's policy exceeds kl_margin * target_kl.
struct PpoOptions {
  double clip_ratio = 0.2;
  int iterations = 80;
  double kl_margin = 1.2;
  double target_kl = 0.01;
};

// report.backtrack_iterations holds the iteration it stopped at (the original's StopIter).
PolicyUpdateReport PpoUpdate(GaussianPolicy& policy, torch::optim::Adam& optimizer,
                             const PolicyBatch& batch, bool lagrangian, double penalty,
                             const PpoOptions& options);

// `iterations` full-batch Adam steps of the value function on the MSE to `targets`, with the
// caller's optimizer (whose moments persist across epochs, as the original's); returns the loss
// before the first step.
double FitValueFunction(TanhMlp& value, torch::optim::Adam& optimizer,
                        const torch::Tensor& observations, const torch::Tensor& targets,
                        int iterations);

}  // namespace cmbrl

// The model-free learner's epoch under way, shared by the learner (policy_opt_learner.cc), which
// rolls and updates it, and its checkpoint (policy_opt_checkpoint.cc), which saves and loads it.
// Internal to the learner: nothing else includes this.
#pragma once

#include <cstdint>
#include <vector>

#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

namespace cmbrl {

// One environment's share of an epoch: its steps in order, cut into paths.
struct EnvTrace {
  std::vector<double> observation;           // the current one
  std::vector<float> observations, actions;  // each step's, row after row
  std::vector<double> rewards, costs;
  // Each path's end (one past its last step) and, where it bootstraps (a time limit or the
  // epoch's end, not a terminal state), the row of `bootstrap_observations` it bootstraps from.
  std::vector<std::int64_t> path_ends, bootstrap_rows;
  std::vector<float> bootstrap_observations;
  double episode_return = 0.0, episode_cost = 0.0;
};

// Rows of floats, `width` each, as an (N, width) tensor.
inline torch::Tensor Rows(const std::vector<float>& values, std::int64_t width) {
  return torch::tensor(values, torch::kFloat).view({-1, width});
}

// An epoch under way: its rollout, then, once the penalty and policy are updated, its value fits.
struct PolicyOptLearner::OpenEpoch {
  std::int64_t steps = 0;   // the epoch's, set when it begins (a last epoch may be cut short)
  std::int64_t rounds = 0;  // of the rollout, done
  std::vector<EnvTrace> traces;
  std::vector<double> episode_returns, episode_costs, episode_lengths;  // finished episodes'
  double step_cost = 0.0;  // every step's cost, finished episodes or not
  double step_raw_cost = 0.0;  // and their raw costs (StepInfo::raw_cost)
  // After the update: the row but for the value losses, the value fits' data, their iterations
  // done (both functions go in step).
  bool updated = false;
  EpochRow row;
  torch::Tensor observations, returns, cost_returns;
  int fitted = 0;
  Timings before;  // the process's totals when it began (zero when loaded)

  // Adds environment k's step of round t (of its `quota` this epoch) to its trace: the
  // observation it acted on and the action (rows of observation_dim and action_dim floats), and
  // from `step` its reward, cost and next observation; where its path ends (a terminal state, a
  // time limit or its quota's end), the path's end and what it bootstraps from, and an ended
  // episode's sums. Returns whether the environment must be reset before its next round.
  bool RecordStep(int k, std::int64_t t, std::int64_t quota, const float* observation,
                  const float* action, const VectorStep& step, std::int64_t observation_dim,
                  std::int64_t action_dim);
};

}  // namespace cmbrl

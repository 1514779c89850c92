// The sheet of the model-free baselines (learners/policy_opt/): a row per epoch of environment
// steps, runs grouped by their algorithm, and the memory of its networks and an epoch's batch.
#include "cmbrl/run/learner_family.h"
#include "cmbrl/run/progress_columns.h"

namespace cmbrl {
namespace {

RunMemory PolicyOptMemory(const RunSizes& sizes) {
  constexpr double kFloat = 4.0;
  const double s = sizes.state_dim, a = sizes.action_dim;
  // Each network's weights, gradients and Adam's two moments, and a few flat copies of the
  // policy's for the trust-region step (counted as 4 more); the epoch's rows (observations,
  // actions, targets), and the activations of a pass over all of them with its gradients
  // (3 copies of each hidden layer's output).
  const PolicyOptimisationOptions& o = sizes.policy_optimisation;
  const auto parameters = [&](const std::vector<int>& hidden, double out) {
    double count = 0.0, in = s;
    for (const int width : hidden) {
      count += (in + 1) * width;
      in = width;
    }
    return count + (in + 1) * out;
  };
  const double policy = parameters(o.policy_hidden, a) + a;  // and the log std
  const double value = parameters(o.value_hidden, 1);
  RunMemory m;
  m.policy_networks = (8 * policy + 2 * 4 * value) * kFloat;
  double activations = 0.0;
  for (const int width : o.policy_hidden) activations += width;
  for (const int width : o.value_hidden) activations += 2.0 * width;
  const double rows = o.steps_per_epoch;
  m.epoch_batch = rows * (s + a + 8) * kFloat + 3 * rows * activations * kFloat;
  return m;
}

}  // namespace

const FamilySheet& PolicyOptFamily() {
  static const FamilySheet sheet = {
      "policy optimisation",
      ProgressLog::kEpochs,
      {"Epoch", kAverageEpRetColumn, kAverageEpCostColumn, "EpLen", "Episodes",
       kCumulativeCostColumn, "CostRate", "Penalty", "KL", "BacktrackIters", "OptimCase", "LossPi",
       "SurrCost", "LossV", "LossVC", "Entropy", kTotalEnvInteractsColumn, kTimeColumn,
       // Added after the columns above (CumulativeRawCost before it, for a Python
       // environment's run): a run begun without it keeps its columns on resume.
       kCpuTimeColumn},
      MethodAxis::kAlgorithm,
      {"policy_optimisation"},
      PolicyOptMemory,
  };
  return sheet;
}

}  // namespace cmbrl

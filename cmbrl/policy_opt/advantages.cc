#include "cmbrl/policy_opt/advantages.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

std::vector<double> DiscountedCumulativeSum(const std::vector<double>& values, double discount) {
  std::vector<double> sums(values.size());
  double running = 0.0;
  for (size_t i = values.size(); i-- > 0;) {
    running = values[i] + discount * running;
    sums[i] = running;
  }
  return sums;
}

PathTargets GaeTargets(const std::vector<double>& rewards, const std::vector<double>& values,
                       double gamma, double lambda) {
  Require(values.size() == rewards.size() + 1,
          "GAE needs one value per step and a bootstrap value: {} rewards, {} values",
          rewards.size(), values.size());
  Require(gamma >= 0 && gamma <= 1, "gamma is {}: expected a number in [0, 1]", gamma);
  Require(lambda >= 0 && lambda <= 1, "lambda is {}: expected a number in [0, 1]", lambda);
  const size_t steps = rewards.size();
  std::vector<double> deltas(steps);
  for (size_t t = 0; t < steps; ++t) {
    deltas[t] = rewards[t] + gamma * values[t + 1] - values[t];
  }
  PathTargets targets;
  targets.advantages = DiscountedCumulativeSum(deltas, gamma * lambda);
  std::vector<double> with_bootstrap(rewards);
  with_bootstrap.push_back(values.back());
  targets.returns = DiscountedCumulativeSum(with_bootstrap, gamma);
  targets.returns.pop_back();
  return targets;
}

void NormaliseAdvantages(std::vector<double>& advantages, bool scale) {
  if (advantages.empty()) return;
  double mean = 0.0;
  for (double a : advantages) mean += a;
  mean /= static_cast<double>(advantages.size());
  double variance = 0.0;
  for (double a : advantages) variance += (a - mean) * (a - mean);
  variance /= static_cast<double>(advantages.size());
  const double std = scale ? std::sqrt(variance) + 1e-8 : 1.0;  // the original's EPS
  for (double& a : advantages) a = (a - mean) / std;
}

}  // namespace cmbrl

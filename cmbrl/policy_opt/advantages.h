// Returns and advantages of the model-free baselines (paper Section V-B; the original ran
// safety-starter-agents): discounted sums and generalised advantage estimation (GAE, Schulman et
// al. 2016), for rewards and for costs alike.
#pragma once

#include <vector>

namespace cmbrl {

// y_t = x_t + discount * y_{t+1}, from the end of the path (the last value seeds y_T).
std::vector<double> DiscountedCumulativeSum(const std::vector<double>& values, double discount);

// One path's GAE advantages and value targets. `values` holds V(s_0) .. V(s_{T-1}) and one more
// entry, the bootstrap value of the state after the last step (0 when the path ended for good).
// delta_t = r_t + gamma V_{t+1} - V_t; advantage_t = sum_k (gamma lambda)^k delta_{t+k};
// return_t = sum_k gamma^k r_{t+k} bootstrapped with the last value. Throws cmbrl::Error when
// values is not one longer than rewards, or gamma or lambda is outside [0, 1].
struct PathTargets {
  std::vector<double> advantages;
  std::vector<double> returns;
};
PathTargets GaeTargets(const std::vector<double>& rewards, const std::vector<double>& values,
                       double gamma, double lambda);

// Advantages normalised to mean 0 and standard deviation 1 (reward advantages), or only centred
// (cost advantages, as the original does). The standard deviation is the population one.
void NormaliseAdvantages(std::vector<double>& advantages, bool scale);

}  // namespace cmbrl

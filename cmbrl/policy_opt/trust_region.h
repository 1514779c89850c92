// The trust-region step of TRPO and CPO (paper Section V-B's baselines; Schulman et al. 2015,
// Achiam et al. 2017), as safety-starter-agents computes it: conjugate gradient on the
// Fisher-vector product, the natural step scaled to the KL target, and CPO's dual solution with
// its recovery cases. The policy's tensors stay outside: these functions see flat vectors.
#pragma once

#include <torch/torch.h>

#include <functional>

namespace cmbrl {

// Solves A x = b for a symmetric positive-definite A given only as a product `apply(v) = A v`,
// starting from x = 0, for `iterations` steps (10 in the original). Thread-compatible.
torch::Tensor ConjugateGradient(const std::function<torch::Tensor(const torch::Tensor&)>& apply,
                                const torch::Tensor& b, int iterations);

// CPO's dual problem at one update. With g the gradient of the policy loss, b that of the
// surrogate cost, H the Fisher matrix (damped), v = H^-1 g and w = H^-1 b:
// q = g^T v, r = b^T v (= g^T w), s = b^T w, and c the constraint's value at the current policy
// ((EpCost - limit) / EpLen, the margin added). The step is x = v_coefficient * v +
// w_coefficient * w, and the parameters become theta - x (line search scaling it).
struct CpoDualInputs {
  double q = 0.0;
  double r = 0.0;
  double s = 0.0;
  double c = 0.0;
  double target_kl = 0.01;
  bool cost_gradient_vanishes = false;  // b^T b <= 1e-8
};

struct CpoDualSolution {
  // 4: feasible, cost gradient zero (plain TRPO step); 3: the whole trust region is feasible;
  // 2: the current policy is feasible and the constraint cuts the region; 1: infeasible, but
  // part of the region is feasible (recovery); 0: no feasible point in the region (infeasible
  // recovery: a step that only lowers the cost).
  int optim_case = 4;
  double lambda = 0.0;  // the KL constraint's multiplier
  double nu = 0.0;      // the cost constraint's multiplier (the logs' Penalty for CPO)
  double a = 0.0;       // q - r^2 / s
  double b = 0.0;       // 2 target_kl - c^2 / s
  double v_coefficient = 0.0;
  double w_coefficient = 0.0;
};

// Thread-safe (pure). Throws cmbrl::Error for a non-positive target_kl or non-finite input.
CpoDualSolution SolveCpoDual(const CpoDualInputs& inputs);

// TRPO's full step along v = H^-1 g: sqrt(2 target_kl / q) v, the largest step whose quadratic
// KL model equals the target.
double NaturalStepScale(double q, double target_kl);

}  // namespace cmbrl

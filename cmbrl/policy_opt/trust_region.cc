#include "cmbrl/policy_opt/trust_region.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cmbrl/core/check.h"
#include "cmbrl/policy_opt/policy_opt_options.h"

namespace cmbrl {

torch::Tensor ConjugateGradient(const std::function<torch::Tensor(const torch::Tensor&)>& apply,
                                const torch::Tensor& b, int iterations) {
  Require(b.dim() == 1, "conjugate gradient needs a flat vector, got shape {}",
          c10::str(b.sizes()));
  Require(iterations >= 1, "conjugate gradient iterations is {}: expected at least 1", iterations);
  torch::Tensor x = torch::zeros_like(b);
  torch::Tensor residual = b.clone();
  torch::Tensor direction = b.clone();
  double residual_dot = residual.dot(residual).item<double>();
  for (int i = 0; i < iterations; ++i) {
    if (residual_dot <= 1e-30) break;  // solved exactly: another step would divide 0 by 0
    const torch::Tensor product = apply(direction);
    const double alpha = residual_dot / (direction.dot(product).item<double>() + kPolicyOptEps);
    x += alpha * direction;
    residual -= alpha * product;
    const double new_dot = residual.dot(residual).item<double>();
    direction = residual + (new_dot / residual_dot) * direction;
    residual_dot = new_dot;
  }
  return x;
}

double NaturalStepScale(double q, double target_kl) {
  Require(target_kl > 0, "target_kl is {}: expected a positive number", target_kl);
  return std::sqrt(2 * target_kl / (q + kPolicyOptEps));
}

CpoDualSolution SolveCpoDual(const CpoDualInputs& in) {
  Require(in.target_kl > 0, "target_kl is {}: expected a positive number", in.target_kl);
  Require(std::isfinite(in.q) && std::isfinite(in.r) && std::isfinite(in.s) &&
              std::isfinite(in.c),
          "CPO dual inputs must be finite: q {}, r {}, s {}, c {}", in.q, in.r, in.s, in.c);
  CpoDualSolution out;
  const double delta = in.target_kl;
  if (in.cost_gradient_vanishes && in.c < 0) {
    out.optim_case = 4;
  } else {
    out.a = in.q - in.r * in.r / in.s;
    out.b = 2 * delta - in.c * in.c / in.s;
    if (in.c < 0 && out.b < 0) {
      out.optim_case = 3;
    } else if (in.c < 0) {
      out.optim_case = 2;
    } else if (out.b >= 0) {
      out.optim_case = 1;
    } else {
      out.optim_case = 0;
    }
  }
  if (out.optim_case >= 3) {
    out.lambda = std::sqrt(in.q / (2 * delta));
    out.nu = 0.0;
  } else if (out.optim_case >= 1) {
    // The dual over lambda splits at r / c: maximise each piece on its interval, keep the better.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::pair<double, double> range_a{0.0, in.r / in.c}, range_b{in.r / in.c, kInf};
    if (in.c >= 0) std::swap(range_a, range_b);
    const auto project = [](double x, std::pair<double, double> range) {
      return std::max(range.first, std::min(range.second, x));
    };
    const double lambda_a = project(std::sqrt(out.a / out.b), range_a);
    const double lambda_b = project(std::sqrt(in.q / (2 * delta)), range_b);
    const auto dual_a = [&](double lambda) {
      return -0.5 * (out.a / (lambda + kPolicyOptEps) + out.b * lambda) -
             in.r * in.c / (in.s + kPolicyOptEps);
    };
    const auto dual_b = [&](double lambda) {
      return -0.5 * (in.q / (lambda + kPolicyOptEps) + 2 * delta * lambda);
    };
    out.lambda = dual_a(lambda_a) >= dual_b(lambda_b) ? lambda_a : lambda_b;
    out.nu = std::max(0.0, out.lambda * in.c - in.r) / (in.s + kPolicyOptEps);
  } else {
    out.lambda = 0.0;
    out.nu = std::sqrt(2 * delta / (in.s + kPolicyOptEps));
  }
  if (out.optim_case > 0) {
    out.v_coefficient = 1.0 / (out.lambda + kPolicyOptEps);
    out.w_coefficient = out.nu / (out.lambda + kPolicyOptEps);
  } else {
    out.v_coefficient = 0.0;
    out.w_coefficient = out.nu;
  }
  return out;
}

}  // namespace cmbrl

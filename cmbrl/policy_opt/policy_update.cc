#include "cmbrl/policy_opt/policy_update.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "cmbrl/core/check.h"
#include "cmbrl/policy_opt/policy_opt_options.h"
#include "cmbrl/policy_opt/trust_region.h"

namespace cmbrl {
namespace {

struct Surrogates {
  torch::Tensor loss;  // the policy loss, scalar
  torch::Tensor cost;  // the surrogate cost, scalar
};

Surrogates Evaluate(const GaussianPolicy& policy, const PolicyBatch& batch,
                    ConstraintHandling handling, double penalty) {
  const torch::Tensor ratio =
      torch::exp(policy.LogProb(batch.observations, batch.actions) - batch.log_probs);
  const torch::Tensor surrogate_advantage = (ratio * batch.advantages).mean();
  const torch::Tensor surrogate_cost = (ratio * batch.cost_advantages).mean();
  torch::Tensor objective = surrogate_advantage;
  if (handling == ConstraintHandling::kLagrangian) {
    objective = (objective - penalty * surrogate_cost) / (1 + penalty);
  }
  return {-objective, surrogate_cost};
}

using FisherProduct = std::function<torch::Tensor(const torch::Tensor&)>;

void CheckTrustRegionInputs(const PolicyBatch& batch, const TrustRegionOptions& o) {
  const std::int64_t n = batch.observations.size(0);
  Require(batch.actions.size(0) == n && batch.advantages.numel() == n &&
              batch.cost_advantages.numel() == n && batch.log_probs.numel() == n,
          "policy batch of {} observations with {} actions, {} advantages, {} cost advantages "
          "and {} log-probabilities: expected as many of each",
          n, batch.actions.size(0), batch.advantages.numel(), batch.cost_advantages.numel(),
          batch.log_probs.numel());
  Require(o.target_kl > 0 && o.damping >= 0 && o.backtrack_coefficient > 0 &&
              o.backtrack_coefficient < 1 && o.backtrack_iterations >= 1,
          "trust region options: target_kl {}, damping {}, backtrack {} x {}: expected a "
          "positive target, non-negative damping, a coefficient in (0, 1) and at least one step",
          o.target_kl, o.damping, o.backtrack_coefficient, o.backtrack_iterations);
}

// CPO's step from the natural gradient v = F^-1 g and the cost's gradient b, with c the
// episode cost's excess over the limit per step: the dual's solution (Achiam et al.), its case
// and multiplier written to `report`.
torch::Tensor CpoStep(const FisherProduct& fisher, const torch::Tensor& v, const torch::Tensor& b,
                      double c, const TrustRegionOptions& o, PolicyUpdateReport& report) {
  CpoDualInputs dual;
  dual.q = v.dot(fisher(v)).item<double>();
  dual.c = c;
  dual.target_kl = o.target_kl;
  dual.cost_gradient_vanishes = b.dot(b).item<double>() <= 1e-8;
  torch::Tensor w = torch::zeros_like(v);
  if (!(dual.cost_gradient_vanishes && c < 0)) {
    w = ConjugateGradient(fisher, b, o.cg_iterations);
    dual.r = w.dot(fisher(v)).item<double>();
    dual.s = w.dot(fisher(w)).item<double>();
  }
  const CpoDualSolution solution = SolveCpoDual(dual);
  report.optim_case = solution.optim_case;
  report.cpo_nu = solution.nu;
  return solution.v_coefficient * v + solution.w_coefficient * w;
}

// The backtracking line search along `step` from the policy's parameters: the first fraction
// whose KL to the old policy (old_mean, old_log_std) is within the target and whose losses
// pass (CPO: the cost may not rise past max(-c, 0)) is kept and reported; if none is, the old
// policy is kept and the report says so.
PolicyUpdateReport LineSearch(GaussianPolicy& policy, const PolicyBatch& batch,
                              ConstraintHandling handling, double penalty,
                              const TrustRegionOptions& o, const torch::Tensor& step, double c,
                              const torch::Tensor& old_mean, const torch::Tensor& old_log_std,
                              PolicyUpdateReport report) {
  const torch::Tensor old_parameters = policy.FlatParameters();
  for (int j = 0; j < o.backtrack_iterations; ++j) {
    const double scale = std::pow(o.backtrack_coefficient, j);
    policy.SetFlatParameters(old_parameters - (scale * step).to(torch::kFloat));
    const torch::NoGradGuard no_grad;
    const Surrogates after = Evaluate(policy, batch, handling, penalty);
    const double new_kl = policy.MeanKl(batch.observations, old_mean, old_log_std).item<double>();
    const double new_loss = after.loss.item<double>();
    const double new_cost = after.cost.item<double>();
    bool accept = new_kl <= o.target_kl;
    if (handling == ConstraintHandling::kCpo) {
      accept = accept && (report.optim_case <= 1 || new_loss <= report.loss_before) &&
               new_cost - report.surrogate_cost_before <= std::max(-c, 0.0);
    } else {
      accept = accept && new_loss <= report.loss_before;
    }
    report.backtrack_iterations = j;
    if (accept) {
      report.kl = new_kl;
      report.loss_after = new_loss;
      report.surrogate_cost_after = new_cost;
      return report;
    }
  }
  // The line search failed: keep the old policy.
  policy.SetFlatParameters(old_parameters);
  report.accepted = false;
  report.kl = 0.0;
  report.loss_after = report.loss_before;
  report.surrogate_cost_after = report.surrogate_cost_before;
  return report;
}

}  // namespace

PolicyUpdateReport TrustRegionUpdate(GaussianPolicy& policy, const PolicyBatch& batch,
                                     ConstraintHandling handling, double penalty,
                                     const TrustRegionOptions& o) {
  CheckTrustRegionInputs(batch, o);
  const std::vector<torch::Tensor> parameters = policy.parameters();
  torch::Tensor old_mean, old_log_std;
  {
    const torch::NoGradGuard no_grad;
    old_mean = policy.Mean(batch.observations);
    old_log_std = policy.log_std().clone();
  }
  const Surrogates before = Evaluate(policy, batch, handling, penalty);
  const torch::Tensor g = FlatGradient(before.loss, parameters).to(torch::kDouble);
  // The Fisher-vector product: the Hessian of the KL at the old policy, damped.
  const auto kl_hessian = policy.KlHessianProduct(batch.observations);
  const FisherProduct fisher = [&](const torch::Tensor& v) {
    return kl_hessian(v.to(torch::kFloat)).to(torch::kDouble) + o.damping * v;
  };

  PolicyUpdateReport report;
  report.loss_before = before.loss.item<double>();
  report.surrogate_cost_before = before.cost.item<double>();
  const torch::Tensor v = ConjugateGradient(fisher, g, o.cg_iterations);
  torch::Tensor step;
  double c = 0.0;
  if (handling == ConstraintHandling::kCpo) {
    const torch::Tensor b = FlatGradient(before.cost, parameters).to(torch::kDouble);
    c = (batch.episode_cost - o.cost_limit + o.cpo_margin) / (batch.episode_length + kPolicyOptEps);
    step = CpoStep(fisher, v, b, c, o, report);
  } else {
    step = v * std::sqrt(2 * o.target_kl / (v.dot(fisher(v)).item<double>() + kPolicyOptEps));
  }
  return LineSearch(policy, batch, handling, penalty, o, step, c, old_mean, old_log_std, report);
}

PolicyUpdateReport PpoUpdate(GaussianPolicy& policy, torch::optim::Adam& optimizer,
                             const PolicyBatch& batch, bool lagrangian, double penalty,
                             const PpoOptions& o) {
  Require(o.clip_ratio > 0 && o.iterations >= 1 && o.kl_margin > 0 && o.target_kl > 0,
          "PPO options: clip_ratio {}, iterations {}, kl_margin {}, target_kl {}: expected "
          "positive values",
          o.clip_ratio, o.iterations, o.kl_margin, o.target_kl);
  torch::Tensor old_mean, old_log_std;
  {
    const torch::NoGradGuard no_grad;
    old_mean = policy.Mean(batch.observations);
    old_log_std = policy.log_std().clone();
  }
  // The clipped advantage: (1 + clip) A where A > 0, (1 - clip) A elsewhere.
  const torch::Tensor clipped_advantage =
      torch::where(batch.advantages > 0, (1 + o.clip_ratio) * batch.advantages,
                   (1 - o.clip_ratio) * batch.advantages);
  const auto losses = [&] {
    const torch::Tensor ratio =
        torch::exp(policy.LogProb(batch.observations, batch.actions) - batch.log_probs);
    torch::Tensor objective = torch::min(ratio * batch.advantages, clipped_advantage).mean();
    const torch::Tensor surrogate_cost = (ratio * batch.cost_advantages).mean();
    if (lagrangian) objective = (objective - penalty * surrogate_cost) / (1 + penalty);
    return std::make_pair(-objective, surrogate_cost);
  };
  PolicyUpdateReport report;
  {
    const auto [loss, cost] = losses();
    report.loss_before = loss.item<double>();
    report.surrogate_cost_before = cost.item<double>();
  }
  for (int i = 0; i < o.iterations; ++i) {
    optimizer.zero_grad();
    losses().first.backward();
    optimizer.step();
    report.backtrack_iterations = i;
    const torch::NoGradGuard no_grad;
    report.kl = policy.MeanKl(batch.observations, old_mean, old_log_std).item<double>();
    if (report.kl > o.kl_margin * o.target_kl) break;
  }
  const torch::NoGradGuard no_grad;
  const auto [loss, cost] = losses();
  report.loss_after = loss.item<double>();
  report.surrogate_cost_after = cost.item<double>();
  return report;
}

double FitValueFunction(TanhMlp& value, torch::optim::Adam& optimizer,
                        const torch::Tensor& observations, const torch::Tensor& targets,
                        int iterations) {
  // The MSE's gradient by hand (TanhMlp::AddSquaredErrorGradient), into tensors that are the
  // parameters' own .grad() throughout: refilled each iteration, never cleared by zero_grad().
  const std::vector<torch::Tensor>& parameters = value.parameters();
  const double rows = static_cast<double>(observations.size(0));
  std::vector<torch::Tensor> gradients;
  for (const torch::Tensor& p : parameters) {
    gradients.push_back(torch::zeros_like(p));
    torch::Tensor parameter = p;
    parameter.mutable_grad() = gradients.back();
  }
  double first_loss = 0.0;
  for (int i = 0; i < iterations; ++i) {
    for (torch::Tensor& g : gradients) g.zero_();
    const double squares =
        value.AddSquaredErrorGradient(observations, targets, 2.0 / rows, gradients);
    if (i == 0) first_loss = squares / rows;
    optimizer.step();
  }
  return first_loss;
}

}  // namespace cmbrl

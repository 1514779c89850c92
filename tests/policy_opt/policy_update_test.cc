#include "cmbrl/policy_opt/policy_update.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/policy_opt/lagrange.h"

namespace cmbrl {
namespace {

// A one-step constrained bandit: reward a, cost 1 when a > 0.5, one step per episode. Without a
// constraint the best policy pushes its mean up for ever; with a limit of 0.2 on the episode
// cost, the best keeps P(a > 0.5) at 0.2.
struct BanditEpoch {
  PolicyBatch batch;
  double mean_cost = 0.0;
};

BanditEpoch CollectBandit(const GaussianPolicy& policy, int samples, at::Generator& generator) {
  const torch::Tensor observations = torch::ones({samples, 1});
  const torch::Tensor actions = policy.Sample(observations, generator);
  const torch::Tensor rewards = actions.squeeze(-1);
  const torch::Tensor costs = (rewards > 0.5).to(torch::kFloat);
  BanditEpoch epoch;
  epoch.mean_cost = costs.mean().item<double>();
  PolicyBatch& b = epoch.batch;
  b.observations = observations;
  b.actions = actions;
  // Episodes of one step: the advantage is the reward minus its mean (a perfect value
  // function), normalised; the cost advantage only centred (the original's conventions).
  b.advantages = (rewards - rewards.mean()) / (rewards.std(/*unbiased=*/false) + 1e-8);
  b.cost_advantages = costs - costs.mean();
  {
    const torch::NoGradGuard no_grad;
    b.log_probs = policy.LogProb(observations, actions);
  }
  b.episode_cost = epoch.mean_cost;
  b.episode_length = 1.0;
  return epoch;
}

// The mean episode cost over the last 20 of `epochs` epochs of training on the bandit.
double TrainBandit(ConstraintHandling handling, int epochs, std::vector<PolicyUpdateReport>* log,
                   bool ppo = false) {
  // Thousands of tiny tensor operations: one thread, so that ctest's parallel processes do not
  // make LibTorch's thread pools wait on each other (the results do not depend on it).
  torch::set_num_threads(1);
  at::Generator generator = MakeCpuGenerator(7);
  GaussianPolicy policy(1, 1, {16, 16}, -0.5, generator);
  LagrangeMultiplier lagrange(LagrangeOptions{1.0, 0.5});
  torch::optim::Adam optimizer(policy.parameters(), torch::optim::AdamOptions(3e-3));
  TrustRegionOptions options;
  options.target_kl = 0.02;
  options.cost_limit = 0.2;
  double late_cost = 0.0;
  for (int epoch = 0; epoch < epochs; ++epoch) {
    const BanditEpoch data = CollectBandit(policy, 2000, generator);
    if (handling == ConstraintHandling::kLagrangian) {
      lagrange.Update(data.mean_cost, options.cost_limit);
    }
    PpoOptions ppo_options;
    ppo_options.target_kl = options.target_kl;
    const PolicyUpdateReport report =
        ppo ? PpoUpdate(policy, optimizer, data.batch, handling == ConstraintHandling::kLagrangian,
                        lagrange.penalty(), ppo_options)
            : TrustRegionUpdate(policy, data.batch, handling, lagrange.penalty(), options);
    if (log != nullptr) log->push_back(report);
    if (epoch >= epochs - 20) late_cost += data.mean_cost / 20;
  }
  return late_cost;
}

TEST(PolicyUpdateTest, AcceptedStepsStayWithinTheKlTarget) {
  std::vector<PolicyUpdateReport> log;
  TrainBandit(ConstraintHandling::kNone, 20, &log);
  int accepted = 0;
  for (const PolicyUpdateReport& report : log) {
    if (!report.accepted) continue;
    ++accepted;
    EXPECT_LE(report.kl, 0.02);
    EXPECT_LE(report.loss_after, report.loss_before);
  }
  EXPECT_GT(accepted, 15);  // the line search rarely fails on this smooth problem
}

TEST(PolicyUpdateTest, TrpoLagrangianAndCpoKeepTheCostLimitWhereTrpoDoesNot) {
  const double trpo = TrainBandit(ConstraintHandling::kNone, 120, nullptr);
  const double lagrangian = TrainBandit(ConstraintHandling::kLagrangian, 120, nullptr);
  const double cpo = TrainBandit(ConstraintHandling::kCpo, 120, nullptr);
  std::cout << "late episode cost: TRPO " << trpo << ", TRPO-L " << lagrangian << ", CPO " << cpo
            << " (limit 0.2)\n";
  EXPECT_GT(trpo, 0.9);  // reward alone drives every action past 0.5
  // Within the limit up to the sampling noise of 2000 draws and the methods' own oscillation.
  EXPECT_LT(lagrangian, 0.2 + 0.05);
  EXPECT_LT(cpo, 0.2 + 0.05);
}

}  // namespace
}  // namespace cmbrl

namespace cmbrl {
namespace {

TEST(PolicyUpdateTest, PpoLagrangianKeepsTheCostLimitWherePpoDoesNot) {
  std::vector<PolicyUpdateReport> log;
  const double ppo = TrainBandit(ConstraintHandling::kNone, 120, &log, /*ppo=*/true);
  const double lagrangian = TrainBandit(ConstraintHandling::kLagrangian, 120, nullptr, true);
  std::cout << "late episode cost: PPO " << ppo << ", PPO-L " << lagrangian << " (limit 0.2)\n";
  EXPECT_GT(ppo, 0.9);
  EXPECT_LT(lagrangian, 0.2 + 0.05);
  // Early stopping keeps each epoch's KL near the margin (1.2 x 0.02, one step past it at most).
  for (const PolicyUpdateReport& report : log) EXPECT_LT(report.kl, 0.1);
}

}  // namespace
}  // namespace cmbrl

namespace cmbrl {
namespace {

// The KL's Hessian by hand (GaussianPolicy::KlHessianProduct) against autograd's double
// backward of MeanKl at the old policy, on random vectors: equal up to rounding.
TEST(PolicyUpdateTest, TheKlHessianProductIsAutogradsDoubleBackward) {
  at::Generator init = MakeCpuGenerator(11);
  GaussianPolicy policy(6, 2, {32, 16}, -0.7, init);
  at::Generator data = MakeCpuGenerator(12);
  const torch::Tensor observations = torch::randn({2500, 6}, data);  // three blocks, one short
  const std::vector<torch::Tensor> parameters = policy.parameters();
  torch::Tensor old_mean, old_log_std;
  {
    const torch::NoGradGuard no_grad;
    old_mean = policy.Mean(observations);
    old_log_std = policy.log_std().clone();
  }
  const torch::Tensor kl_gradient = FlatGradient(
      policy.MeanKl(observations, old_mean, old_log_std), parameters, /*create_graph=*/true);
  const auto by_hand = policy.KlHessianProduct(observations);
  for (int trial = 0; trial < 3; ++trial) {
    const torch::Tensor v = torch::randn({kl_gradient.numel()}, data);
    const torch::Tensor reference = FlatGradient((kl_gradient * v).sum(), parameters);
    const torch::Tensor product = by_hand(v);
    const double scale = reference.abs().max().item<double>();
    EXPECT_GT(scale, 0.1);
    EXPECT_LT((product - reference).abs().max().item<double>(), 1e-5 * scale) << "trial " << trial;
    // The log std's part: 2 v per dimension (its second derivative where eps is negligible).
    EXPECT_TRUE(torch::allclose(product.slice(0, -2), 2 * v.slice(0, -2), 1e-5, 1e-6));
  }
  EXPECT_THROW(by_hand(torch::zeros({3})), Error);
}

// The value fit's hand-written, blocked gradient against LibTorch's autograd on the full batch:
// the same Adam steps up to rounding, the same loss before the first.
TEST(PolicyUpdateTest, ValueFitsFollowAutogradsGradient) {
  at::Generator a_init = MakeCpuGenerator(5), b_init = MakeCpuGenerator(5);
  TanhMlp fitted(6, {32, 16}, 1, a_init), reference(6, {32, 16}, 1, b_init);
  at::Generator data = MakeCpuGenerator(6);
  const torch::Tensor observations = torch::randn({2500, 6}, data);  // three blocks, one short
  const torch::Tensor targets = torch::sin(observations.sum(-1)) * 3;
  torch::optim::Adam fitted_adam(fitted.parameters(), torch::optim::AdamOptions(1e-3));
  torch::optim::Adam reference_adam(reference.parameters(), torch::optim::AdamOptions(1e-3));
  const double loss = FitValueFunction(fitted, fitted_adam, observations, targets, 20);
  double reference_loss = 0.0;
  for (int i = 0; i < 20; ++i) {
    reference_adam.zero_grad();
    const torch::Tensor mse =
        (reference.Forward(observations).squeeze(-1) - targets).pow(2).mean();
    if (i == 0) reference_loss = mse.item<double>();
    mse.backward();
    reference_adam.step();
  }
  EXPECT_NEAR(loss, reference_loss, 1e-5 * reference_loss);
  for (size_t k = 0; k < fitted.parameters().size(); ++k) {
    EXPECT_TRUE(torch::allclose(fitted.parameters()[k], reference.parameters()[k], 1e-4, 1e-6))
        << "parameter " << k << " max difference "
        << (fitted.parameters()[k] - reference.parameters()[k]).abs().max().item<double>();
  }
  // And it fits: the loss falls.
  const double later = FitValueFunction(fitted, fitted_adam, observations, targets, 1);
  EXPECT_LT(later, loss);
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/planning/elite_rule.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <vector>

namespace cmbrl {
namespace {

std::vector<long> AsVector(const torch::Tensor& indices) {
  const torch::Tensor host = indices.to(torch::kLong).contiguous();
  return {host.data_ptr<long>(), host.data_ptr<long>() + host.numel()};
}

TEST(EliteWeightsTest, RobustRuleKeepsOnlyFeasibleSamplesWhenEnough) {
  // Samples 0..6 feasible with reward cost 10 + i; 7..19 infeasible but rewarding (cost i).
  torch::Tensor reward = torch::arange(20, torch::kFloat);
  reward.slice(0, 0, 7) += 10;
  torch::Tensor constraint = torch::ones({20});
  constraint.slice(0, 0, 7).zero_();
  constraint.slice(0, 7, 12).fill_(0.001f);  // barely violating: the penalty still ranks them
  const torch::Tensor robust = EliteWeights({reward, constraint}, {EliteRule::kRobust, 12, 5, 0});
  EXPECT_TRUE(torch::equal(robust, (torch::arange(20) < 7).to(torch::kFloat)));
  const torch::Tensor penalty =
      EliteWeights({reward, constraint}, {EliteRule::kPenalty, 12, 5, 500.0});
  EXPECT_EQ(penalty.sum().item<float>(), 12.0f);
  EXPECT_EQ(penalty.slice(0, 0, 12).sum().item<float>(), 12.0f);  // 7 feasible + 5 barely
}

TEST(EliteWeightsTest, RobustRulePadsWithTheLeastViolatingWhenTooFew) {
  // Two feasible samples (3 and 8); constraint costs rise with the index otherwise.
  const torch::Tensor reward = torch::zeros({10});
  torch::Tensor constraint = torch::arange(1, 11, torch::kFloat);
  constraint[3] = 0;
  constraint[8] = 0;
  const torch::Tensor weights = EliteWeights({reward, constraint}, {EliteRule::kRobust, 5, 5, 0});
  // Feasible 3 and 8, plus the first 5 - 2 = 3 by constraint cost: 3 and 8 again (they sort
  // first, so they count twice), then sample 0.
  const torch::Tensor expected = torch::tensor({1.f, 0.f, 0.f, 2.f, 0.f, 0.f, 0.f, 0.f, 2.f, 0.f});
  EXPECT_TRUE(torch::equal(weights, expected)) << weights;
}

TEST(RankSamplesTest, RobustOrderPutsTheFeasibleFirstByRewardThenTheLeastViolating) {
  const torch::Tensor reward = torch::tensor({5.f, 1.f, 3.f, 0.f, 2.f, 4.f, -1.f});
  const torch::Tensor constraint = torch::tensor({0.f, 2.f, 0.f, 1.f, 0.f, 1.f, 3.f});
  // Feasible: 4 (2), 2 (3), 0 (5); then constraint 1: 3 (0) before 5 (4); then 1 (2); then 6 (3).
  EXPECT_EQ(AsVector(RankSamples({reward, constraint}, {EliteRule::kRobust, 3, 2, 0})),
            (std::vector<long>{4, 2, 0, 3, 5, 1, 6}));
  // The penalised order weighs the violations: reward + 10 * constraint.
  EXPECT_EQ(AsVector(RankSamples({reward, constraint}, {EliteRule::kPenalty, 3, 2, 10.0})),
            (std::vector<long>{4, 2, 0, 3, 5, 1, 6}));
  // At penalty 0 only the reward counts.
  EXPECT_EQ(AsVector(RankSamples({reward, constraint}, {EliteRule::kPenalty, 3, 2, 0.0})),
            (std::vector<long>{6, 3, 1, 4, 2, 5, 0}));
}

TEST(RankSamplesTest, TiesKeepIndexOrderAndWithNoneFeasibleTheLeastViolatingLeads) {
  const torch::Tensor reward = torch::tensor({1.f, 1.f, 0.f, 1.f});
  const torch::Tensor constraint = torch::tensor({2.f, 1.f, 2.f, 1.f});
  EXPECT_EQ(AsVector(RankSamples({reward, constraint}, {EliteRule::kRobust, 2, 1, 0})),
            (std::vector<long>{1, 3, 2, 0}));
}

}  // namespace
}  // namespace cmbrl

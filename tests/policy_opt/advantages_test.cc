#include "cmbrl/policy_opt/advantages.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/error_message.h"

namespace cmbrl {
namespace {

constexpr double kAdvantageTol = 1e-12;  // double arithmetic on a handful of terms

TEST(AdvantagesTest, GaeOnAShortHandComputedPath) {
  // gamma 0.9, lambda 0.8 (gamma lambda 0.72); V = 0.5, 0.2, 0.1 and a bootstrap value of 0.3.
  // deltas: 1 + 0.18 - 0.5 = 0.68; 0 + 0.09 - 0.2 = -0.11; 2 + 0.27 - 0.1 = 2.17.
  const PathTargets t = GaeTargets({1, 0, 2}, {0.5, 0.2, 0.1, 0.3}, 0.9, 0.8);
  ASSERT_EQ(t.advantages.size(), 3u);
  EXPECT_NEAR(t.advantages[2], 2.17, kAdvantageTol);
  EXPECT_NEAR(t.advantages[1], -0.11 + 0.72 * 2.17, kAdvantageTol);
  EXPECT_NEAR(t.advantages[0], 0.68 + 0.72 * (-0.11 + 0.72 * 2.17), kAdvantageTol);
  // Returns bootstrapped with 0.3: 2 + 0.27 = 2.27; 0.9 * 2.27 = 2.043; 1 + 0.9 * 2.043.
  EXPECT_NEAR(t.returns[2], 2.27, kAdvantageTol);
  EXPECT_NEAR(t.returns[1], 2.043, kAdvantageTol);
  EXPECT_NEAR(t.returns[0], 2.8387, kAdvantageTol);
}

TEST(AdvantagesTest, LambdaOneGivesReturnsMinusValues) {
  const std::vector<double> rewards = {0.3, -1.0, 2.0, 0.5};
  const std::vector<double> values = {0.1, 0.4, -0.2, 0.7, 0.0};
  const PathTargets t = GaeTargets(rewards, values, 0.95, 1.0);
  for (size_t i = 0; i < rewards.size(); ++i) {
    EXPECT_NEAR(t.advantages[i], t.returns[i] - values[i], kAdvantageTol) << i;
  }
}

TEST(AdvantagesTest, RewardAdvantagesAreStandardisedCostAdvantagesOnlyCentred) {
  std::vector<double> rewards = {1, 2, 3, 6};
  NormaliseAdvantages(rewards, /*scale=*/true);
  double mean = 0, squares = 0;
  for (double a : rewards) mean += a / 4;
  for (double a : rewards) squares += (a - mean) * (a - mean) / 4;
  EXPECT_NEAR(mean, 0.0, kAdvantageTol);
  EXPECT_NEAR(squares, 1.0, 1e-7);  // the 1e-8 added to the deviation
  std::vector<double> costs = {1, 2, 3, 6};
  NormaliseAdvantages(costs, /*scale=*/false);
  EXPECT_EQ(costs, (std::vector<double>{-2, -1, 0, 3}));
}

TEST(AdvantagesTest, BadInputsAreNamed) {
  EXPECT_THAT(testing::ErrorMessage([] { GaeTargets({1, 2}, {0, 0}, 0.99, 0.97); }),
              ::testing::HasSubstr("2 rewards, 2 values"));
  EXPECT_THAT(testing::ErrorMessage([] { GaeTargets({1}, {0, 0}, 1.5, 0.97); }),
              ::testing::HasSubstr("gamma is 1.5"));
}

}  // namespace
}  // namespace cmbrl

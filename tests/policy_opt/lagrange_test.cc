#include "cmbrl/policy_opt/lagrange.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "tests/error_message.h"

namespace cmbrl {
namespace {

TEST(LagrangeMultiplierTest, StartsAtItsInitialPenaltyAndTakesAdamsFirstStep) {
  LagrangeMultiplier lagrange;
  EXPECT_NEAR(lagrange.penalty(), 1.0, 1e-12);
  const double before = lagrange.parameter();
  lagrange.Update(/*episode_cost=*/20.0, /*cost_limit=*/10.0);
  // Adam's first step is lr * g / (|g| + eps) whatever the gradient's size: p rises by 0.05.
  EXPECT_NEAR(lagrange.parameter() - before, 0.05, 1e-9);
  // (0.05 to within Adam's epsilon: 0.05 * 10 / (10 + 1e-8) differs by 5e-11.)
  EXPECT_NEAR(lagrange.penalty(), std::log1p(std::exp(before + 0.05)), 1e-10);
}

TEST(LagrangeMultiplierTest, RisesWhileCostExceedsTheLimitAndFallsBelowIt) {
  LagrangeMultiplier lagrange;
  double previous = lagrange.penalty();
  for (int epoch = 0; epoch < 20; ++epoch) {
    lagrange.Update(25.0, 10.0);
    EXPECT_GT(lagrange.penalty(), previous) << "epoch " << epoch;
    previous = lagrange.penalty();
  }
  // Adam's momentum carries the rise a few steps past the turn; then the penalty falls steadily.
  for (int epoch = 0; epoch < 10; ++epoch) lagrange.Update(2.0, 10.0);
  previous = lagrange.penalty();
  for (int epoch = 0; epoch < 20; ++epoch) {
    lagrange.Update(2.0, 10.0);
    EXPECT_LT(lagrange.penalty(), previous) << "epoch " << epoch;
    previous = lagrange.penalty();
  }
  EXPECT_GT(lagrange.penalty(), 0.0);  // softplus keeps it positive
}

TEST(LagrangeMultiplierTest, StateRoundTripsAndBadSettingsAreNamed) {
  LagrangeMultiplier a, b;
  a.Update(30, 10);
  a.Update(5, 10);
  b.set_state(a.state());
  a.Update(12, 10);
  b.Update(12, 10);
  EXPECT_EQ(a.penalty(), b.penalty());
  EXPECT_THAT(testing::ErrorMessage([] { LagrangeMultiplier({0.0}); }),
              ::testing::HasSubstr("initial_penalty is 0"));
  EXPECT_THAT(testing::ErrorMessage([] { LagrangeMultiplier().Update(NAN, 10); }),
              ::testing::HasSubstr("must be finite"));
}

}  // namespace
}  // namespace cmbrl

// Random shooting (the MPC-random baseline).
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "cmbrl/planning/planner_registry.h"
#include "tests/planning/analytic_objectives.h"

namespace cmbrl {
namespace {

using testing::QuadraticObjective;

TEST(RandomShootingTest, FindsAnOptimumInFewDimensions) {
  PlannerSettings settings;
  settings.problem.horizon = 1;
  QuadraticObjective objective({0.5f, -0.3f});
  const PlanResult plan = MakePlanner("random", settings, 3)->Plan(objective);
  // 5000 uniform samples of [-1, 1]^2: the nearest lies within about 0.02 of any point.
  EXPECT_LT((plan.action - torch::tensor({0.5f, -0.3f})).abs().max().item<float>(), 0.05f);
  EXPECT_EQ(plan.diagnostics.infeasible_elite_fraction.item<float>(), 0.0f);
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/eval/evaluation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/error_message.h"

namespace cmbrl {
namespace {

// A plan of `samples` sequences seen by `members` members: path (n, e) starts at (n, e).
PlanPaths SyntheticPlan(int samples, int members) {
  PlanPaths plan;
  plan.members = members;
  for (int n = 0; n < samples; ++n) {
    for (int e = 0; e < members; ++e)
      plan.population.push_back({{{1.0 * n, 1.0 * e}}, true, false});
  }
  for (int e = 0; e < members; ++e) plan.chosen.push_back({{{-1.0, 1.0 * e}}, true, true});
  return plan;
}

TEST(SelectPredictionsTest, KeepsExactlyTheSamplesAskedForSpreadEvenlyWithEveryMember) {
  const PlanPaths plan = SyntheticPlan(500, 4);
  const std::vector<PredictedPath> paths = SelectPredictions(plan, 8);
  ASSERT_EQ(paths.size(), (8u + 1u) * 4u);  // (a stride of 500 / 8 = 62 kept 9 before v0.7)
  std::vector<double> samples;
  for (size_t i = 0; i < 8 * 4; i += 4) samples.push_back(paths[i].points[0].x);
  EXPECT_EQ(samples, (std::vector<double>{0, 62, 125, 187, 250, 312, 375, 437}));
  for (size_t i = 0; i < paths.size(); ++i) {
    EXPECT_EQ(paths[i].points[0].y, static_cast<double>(i % 4)) << "member order";
    EXPECT_EQ(paths[i].chosen, i >= 32);
  }
}

TEST(SelectPredictionsTest, ASmallPopulationGivesAllOfIt) {
  EXPECT_EQ(SelectPredictions(SyntheticPlan(24, 5), 1000).size(), (24u + 1u) * 5u);
  EXPECT_EQ(SelectPredictions(SyntheticPlan(24, 5), 1).size(), 2u * 5u);
  EXPECT_THAT(testing::ErrorMessage([] { SelectPredictions(SyntheticPlan(3, 1), 0); }),
              ::testing::HasSubstr("samples is 0: expected at least 1"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/report/curves.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/error_message.h"
#include "tests/report/report_fixture.h"

namespace cmbrl {
namespace {

using testing::ReportTest;

TEST_F(ReportTest, LearningCurvesAverageOverSeedsThatReachEachStep) {
  const std::vector<RunRecord> runs = ReadSweep(sweep_.string());
  const std::vector<LearningCurve> curves =
      LearningCurves(runs, "PointGoal1", CurveMetric::kReturn, 100, 100);
  ASSERT_EQ(curves.size(), 2u);
  EXPECT_EQ(curves[0].planner, "rce");
  EXPECT_EQ(curves[0].steps, (std::vector<double>{100, 200, 300, 400}));
  // Returns 0,1,2,3 (seed 0) and 1,2,3,4 (seed 1): means 0.5 .. 3.5.
  EXPECT_EQ(curves[0].mean, (std::vector<double>{0.5, 1.5, 2.5, 3.5}));
  EXPECT_NEAR(curves[0].std[0], std::sqrt(0.5), 1e-12);
  // CEM's seed 1 stops at 300: the point at 400 has seed 0 alone.
  EXPECT_EQ(curves[1].mean.back(), 3.0);
  EXPECT_EQ(curves[1].std.back(), 0.0);
}

}  // namespace
}  // namespace cmbrl

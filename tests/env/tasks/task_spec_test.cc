#include "cmbrl/env/tasks/task_spec.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cmbrl/core/check.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

TEST(GoalSpecTest, PaperSuiteCountsAndTiming) {
  // Facts B0: 7 / 14 hazards, 1 / 2 constrained vases, goal keep-out 0.35, action repeat
  // 3 (Point) / 2 (Car), episodes of 300 / 150 env steps, ego-state observations.
  const NavigationTaskSpec pg1 = NavigationTaskSpecByName("PointGoal1", Variant::kPaper);
  EXPECT_EQ(pg1.num_hazards, 7);
  EXPECT_EQ(pg1.num_vases, 1);
  EXPECT_TRUE(pg1.vases_constrained);
  EXPECT_DOUBLE_EQ(pg1.goal_keepout, 0.35);
  EXPECT_DOUBLE_EQ(pg1.vase_velocity_threshold, 1e-3);
  EXPECT_EQ(pg1.action_repeat, 3);
  EXPECT_EQ(pg1.max_env_steps, 300);
  EXPECT_EQ(pg1.observation, ObservationKind::kEgoState);
  EXPECT_DOUBLE_EQ(pg1.placement.x_max, 1.5);
  const NavigationTaskSpec cg2 = NavigationTaskSpecByName("CarGoal2", Variant::kPaper);
  EXPECT_EQ(cg2.num_hazards, 14);
  EXPECT_EQ(cg2.num_vases, 2);
  EXPECT_EQ(cg2.action_repeat, 2);
  EXPECT_EQ(cg2.max_env_steps, 150);
  EXPECT_DOUBLE_EQ(cg2.placement.x_min, -2.0);
}

TEST(GoalSpecTest, StandardSuiteCountsAndTiming) {
  // Facts A1, A4: 8 hazards and 1 unconstrained vase / 10 and 10 constrained; 1000 steps.
  const NavigationTaskSpec pg1 = NavigationTaskSpecByName("PointGoal1", Variant::kStandard);
  EXPECT_EQ(pg1.num_hazards, 8);
  EXPECT_EQ(pg1.num_vases, 1);
  EXPECT_FALSE(pg1.vases_constrained);
  EXPECT_DOUBLE_EQ(pg1.goal_keepout, 0.305);
  EXPECT_EQ(pg1.action_repeat, 1);
  EXPECT_EQ(pg1.frame_skip, 10);
  EXPECT_EQ(pg1.max_env_steps, 1000);
  EXPECT_EQ(pg1.observation, ObservationKind::kLidar);
  const NavigationTaskSpec cg2 = NavigationTaskSpecByName("CarGoal2", Variant::kStandard);
  EXPECT_EQ(cg2.num_hazards, 10);
  EXPECT_EQ(cg2.num_vases, 10);
  EXPECT_TRUE(cg2.vases_constrained);
}

TEST(GoalSpecTest, UnknownTaskAndLevelAreNamed) {
  EXPECT_THAT(ErrorMessage([&] { NavigationTaskSpecByName("PointGoal3", Variant::kPaper); }),
              ::testing::AllOf(::testing::StartsWith("unknown task 'PointGoal3': expected one of "
                                                     "PointGoal1, PointGoal2, CarGoal1, CarGoal2, "
                                                     "PointButton0, "),
                               ::testing::EndsWith("CarCircle2 (or an environment given from "
                                                   "Python)")));
  EXPECT_THAT(ErrorMessage([&] { NavigationTaskSpecByName("python:m.make()", Variant::kPaper); }),
              ::testing::HasSubstr("is an environment given from Python: train, resume and load "
                                   "it from Python"));
  EXPECT_THROW(MakeNavigationTaskSpec({"CarGoal0", TaskFamily::kGoal, RobotKind::kCar, 0}, Variant::kPaper), Error);
}

TEST(GoalSpecTest, VariantNamesRoundTripAndUnknownOnesAreNamed) {
  EXPECT_EQ(ParseVariant("paper"), Variant::kPaper);
  EXPECT_EQ(ParseVariant(VariantName(Variant::kStandard)), Variant::kStandard);
  EXPECT_EQ(ParseVariant(VariantName(Variant::kPaperLidar)), Variant::kPaperLidar);
  EXPECT_THAT(ErrorMessage([&] { ParseVariant("stock"); }),
              ::testing::HasSubstr("unknown variant 'stock'"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/env/tasks/layout.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cmbrl/core/check.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

struct Keepout {
  Vec2 position;
  double radius;
  const char* what;
};

std::vector<Keepout> KeepoutsOf(const NavigationTaskSpec& spec, const NavigationLayout& layout) {
  std::vector<Keepout> objects = {{layout.robot.position, spec.robot_keepout, "robot"},
                                  {layout.goal, spec.goal_keepout, "goal"}};
  for (const Vec2& h : layout.hazards) objects.push_back({h, spec.hazard_keepout, "hazard"});
  for (const Pose2& v : layout.vases) objects.push_back({v.position, spec.vase_keepout, "vase"});
  return objects;
}

// Every pair is at least the sum of its keep-outs apart, every object lies in the placement
// area shrunk by its own keep-out, every yaw in [0, 2 pi).
void ExpectValid(const NavigationTaskSpec& spec, const NavigationLayout& layout) {
  const std::vector<Keepout> objects = KeepoutsOf(spec, layout);
  for (size_t i = 0; i < objects.size(); ++i) {
    const Keepout& a = objects[i];
    ASSERT_GE(a.position.x, spec.placement.x_min + a.radius) << a.what;
    ASSERT_LE(a.position.x, spec.placement.x_max - a.radius) << a.what;
    ASSERT_GE(a.position.y, spec.placement.y_min + a.radius) << a.what;
    ASSERT_LE(a.position.y, spec.placement.y_max - a.radius) << a.what;
    for (size_t j = i + 1; j < objects.size(); ++j) {
      const Keepout& b = objects[j];
      ASSERT_GE(Distance(a.position, b.position), a.radius + b.radius + spec.placement_margin)
          << a.what << " " << i << " and " << b.what << " " << j;
    }
  }
  ASSERT_GE(layout.robot.yaw, 0.0);
  ASSERT_LT(layout.robot.yaw, 2 * M_PI);
  for (const Pose2& vase : layout.vases) {
    ASSERT_GE(vase.yaw, 0.0);
    ASSERT_LT(vase.yaw, 2 * M_PI);
  }
}

class NavigationLayoutTest : public ::testing::TestWithParam<std::tuple<std::string, Variant>> {
 protected:
  NavigationTaskSpec spec_ = NavigationTaskSpecByName(std::get<0>(GetParam()), std::get<1>(GetParam()));
};

TEST_P(NavigationLayoutTest, KeepoutsHoldOverAThousandLayouts) {
  Rng rng(2024);
  for (int i = 0; i < 1000; ++i) {
    const NavigationLayout layout = SampleLayout(spec_, rng);
    ASSERT_EQ(static_cast<int>(layout.hazards.size()), spec_.num_hazards);
    ASSERT_EQ(static_cast<int>(layout.vases.size()), spec_.num_vases);
    ExpectValid(spec_, layout);
  }
}

TEST_P(NavigationLayoutTest, ResampledGoalsKeepTheirDistance) {
  Rng rng(11);
  for (int i = 0; i < 1000; ++i) {
    NavigationLayout layout = SampleLayout(spec_, rng);
    const Vec2 before = layout.goal;
    ASSERT_TRUE(ResampleGoal(spec_, layout, rng));
    ExpectValid(spec_, layout);
    ASSERT_NE(layout.goal, before);
  }
}

TEST_P(NavigationLayoutTest, SameSeedSameLayoutDifferentSeedsDifferentLayouts) {
  Rng a(5), b(5), c(6);
  const NavigationLayout first = SampleLayout(spec_, a);
  const NavigationLayout again = SampleLayout(spec_, b);
  const NavigationLayout other = SampleLayout(spec_, c);
  EXPECT_EQ(first.robot.position, again.robot.position);
  EXPECT_EQ(first.goal, again.goal);
  for (int i = 0; i < spec_.num_hazards; ++i) EXPECT_EQ(first.hazards[i], again.hazards[i]);
  EXPECT_NE(first.robot.position, other.robot.position);
  EXPECT_NE(first.goal, other.goal);
}

TEST_P(NavigationLayoutTest, PositionsCoverThePlacementArea) {
  // Uniform draws: over 1000 layouts the robot visits all four quadrants of the area and
  // reaches within 10% of each shrunk edge.
  Rng rng(3);
  double x_min = 1e9, x_max = -1e9;
  int quadrants[4] = {0, 0, 0, 0};
  for (int i = 0; i < 1000; ++i) {
    const Vec2 p = SampleLayout(spec_, rng).robot.position;
    x_min = std::min(x_min, p.x);
    x_max = std::max(x_max, p.x);
    ++quadrants[(p.x > 0) + 2 * (p.y > 0)];
  }
  const double reach = spec_.placement.x_max - spec_.robot_keepout;
  EXPECT_LT(x_min, -0.9 * reach);
  EXPECT_GT(x_max, 0.9 * reach);
  for (int count : quadrants) EXPECT_GT(count, 150);
}

INSTANTIATE_TEST_SUITE_P(AllTasks, NavigationLayoutTest,
                         ::testing::Combine(::testing::Values("PointGoal1", "PointGoal2",
                                                              "CarGoal1", "CarGoal2"),
                                            ::testing::Values(Variant::kPaper, Variant::kStandard)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + VariantName(std::get<1>(info.param));
                         });

TEST(NavigationLayoutErrorTest, ImpossibleLayoutIsReportedNotLooped) {
  NavigationTaskSpec spec = NavigationTaskSpecByName("PointGoal1", Variant::kPaper);
  spec.num_hazards = 200;  // cannot fit in 3 x 3 m with 0.36 m between centres
  spec.layout_tries = 20;
  Rng rng(0);
  EXPECT_EQ(ErrorMessage([&] { SampleLayout(spec, rng); }),
            "no layout of PointGoal1 fits its keep-outs after 20 tries");
}

TEST(NavigationLayoutErrorTest, GoalThatCannotFitLeavesTheLayoutAlone) {
  NavigationTaskSpec spec = NavigationTaskSpecByName("PointGoal1", Variant::kPaper);
  Rng rng(0);
  NavigationLayout layout = SampleLayout(spec, rng);
  const Vec2 goal = layout.goal;
  spec.goal_keepout = 5.0;  // larger than the area
  EXPECT_FALSE(ResampleGoal(spec, layout, rng));
  EXPECT_EQ(layout.goal, goal);
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/env/observation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cmbrl {
namespace {

// Exact-arithmetic cases up to rounding of sin/cos: 1e-12 m.
constexpr double kObservationTol = 1e-12;

RobotFrame PlanarFrame(double x, double y, double z, double yaw) {
  RobotFrame frame;
  frame.position = {x, y, z};
  const double c = std::cos(yaw), s = std::sin(yaw);
  frame.rotation = {c, -s, 0, s, c, 0, 0, 0, 1};
  return frame;
}

TEST(EgoXYTest, RotatesWorldOffsetsIntoTheRobotFrame) {
  // Robot at (1, 2) facing +y: a point 1 m further along +y is straight ahead, a point at
  // world -x of the robot is on its left.
  const RobotFrame frame = PlanarFrame(1, 2, 0.1, M_PI / 2);
  const Vec2 ahead = EgoXY(frame, {1, 3});
  EXPECT_NEAR(ahead.x, 1.0, kObservationTol);
  EXPECT_NEAR(ahead.y, 0.0, kObservationTol);
  const Vec2 left = EgoXY(frame, {0, 2});
  EXPECT_NEAR(left.x, 0.0, kObservationTol);
  EXPECT_NEAR(left.y, 1.0, kObservationTol);
  const Vec2 behind_right = EgoXY(frame, {2, 1});
  EXPECT_NEAR(behind_right.x, -1.0, kObservationTol);
  EXPECT_NEAR(behind_right.y, -1.0, kObservationTol);
}

TEST(EgoXYTest, UsesTheRobotHeightWhenTheRobotTilts) {
  // Pitched down by 90 degrees about y: body x points to world -z. The floor point directly
  // below a robot at height 0.5 then lies 0.5 m ahead.
  RobotFrame frame;
  frame.position = {0, 0, 0.5};
  frame.rotation = {0, 0, 1, 0, 1, 0, -1, 0, 0};
  const Vec2 ego = EgoXY(frame, {0, 0});
  EXPECT_NEAR(ego.x, 0.5, kObservationTol);
  EXPECT_NEAR(ego.y, 0.0, kObservationTol);
}

TEST(PseudoLidarTest, ObjectOnABinEdgeFillsItsBinAndAliasesToThePreviousOne) {
  const RobotFrame frame = PlanarFrame(0, 0, 0, 0);
  double bins[16];
  PseudoLidar(frame, {{1.0, 0.0}}, 16, 3.0, bins);
  // Angle 0 is bin 0 with alias 0: bin 0 reads (3 - 1) / 3, the previous bin (15) gets
  // (1 - 0) of it and the next (1) gets 0.
  EXPECT_NEAR(bins[0], 2.0 / 3.0, kObservationTol);
  EXPECT_NEAR(bins[15], 2.0 / 3.0, kObservationTol);
  EXPECT_NEAR(bins[1], 0.0, kObservationTol);
  for (int i = 2; i < 15; ++i) EXPECT_EQ(bins[i], 0.0) << "bin " << i;
}

TEST(PseudoLidarTest, ObjectInsideABinSplitsBetweenItsNeighbours) {
  const RobotFrame frame = PlanarFrame(0, 0, 0, 0);
  const double bin_size = 2 * M_PI / 16;
  // 1.25 bins counter-clockwise at 1.5 m: bin 1, alias 0.25, reading 0.5.
  const double angle = 1.25 * bin_size;
  double bins[16];
  PseudoLidar(frame, {{1.5 * std::cos(angle), 1.5 * std::sin(angle)}}, 16, 3.0, bins);
  EXPECT_NEAR(bins[1], 0.5, kObservationTol);
  EXPECT_NEAR(bins[2], 0.25 * 0.5, kObservationTol);
  EXPECT_NEAR(bins[0], 0.75 * 0.5, kObservationTol);
}

TEST(PseudoLidarTest, BinsKeepTheNearestObjectAndIgnoreFarOnes) {
  const RobotFrame frame = PlanarFrame(0, 0, 0, 0);
  const double bin_size = 2 * M_PI / 16;
  const double angle = 8.5 * bin_size;  // middle of bin 8, behind the robot
  const Vec2 direction{std::cos(angle), std::sin(angle)};
  double bins[16];
  PseudoLidar(frame, {2.4 * direction, 0.6 * direction, 3.5 * direction}, 16, 3.0, bins);
  EXPECT_NEAR(bins[8], (3.0 - 0.6) / 3.0, kObservationTol);
  EXPECT_NEAR(bins[7], 0.5 * (3.0 - 0.6) / 3.0, kObservationTol);
  EXPECT_NEAR(bins[9], 0.5 * (3.0 - 0.6) / 3.0, kObservationTol);
  PseudoLidar(frame, {3.5 * direction}, 16, 3.0, bins);
  for (double value : bins) EXPECT_EQ(value, 0.0);
}

TEST(PseudoLidarTest, AnglesAreMeasuredFromTheRobotHeading) {
  // Robot facing world +y; an object at world +y is at ego angle 0 (bin 0), one at world +x is
  // at ego angle -90 degrees = 270 degrees (bin 12).
  const RobotFrame frame = PlanarFrame(0, 0, 0, M_PI / 2);
  double bins[16];
  PseudoLidar(frame, {{0.0, 1.0}}, 16, 3.0, bins);
  EXPECT_NEAR(bins[0], 2.0 / 3.0, 1e-9);
  PseudoLidar(frame, {{1.0, 0.0}}, 16, 3.0, bins);
  // 270 degrees sits on the start of bin 12 (up to rounding, possibly the end of bin 11).
  EXPECT_NEAR(std::max(bins[12], bins[11]), 2.0 / 3.0, 1e-9);
  EXPECT_EQ(bins[0], 0.0);
}

}  // namespace
}  // namespace cmbrl

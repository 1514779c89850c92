// The stock two-wheel Car (facts A6).
#include <gtest/gtest.h>

#include <cmath>

#include "tests/env/test_scenes.h"

namespace cmbrl {
namespace {

using testing::FarEnv;
using testing::Hold;

TEST(TwoWheelCarTest, EqualPositiveTorquesDriveTowardBodyMinusY) {
  NavigationEnv env = FarEnv("CarGoal1", Variant::kStandard);
  Hold(env, {1.0, 1.0}, 4.0);
  const Pose2 pose = env.Scene().robot;
  // Started at the origin with yaw 0: body -y is world -y. The wheels saturate at 0.02 N m;
  // a 4 s run covers well over a metre (about 0.65 m/s), drifting sideways far less.
  EXPECT_LT(pose.position.y, -1.5);
  EXPECT_LT(std::abs(pose.position.x), 0.5 * std::abs(pose.position.y));
  EXPECT_GT(testing::RobotUpZ(env), 0.99);
}

TEST(TwoWheelCarTest, OppositeTorquesTurnItOnTheSpot) {
  NavigationEnv env = FarEnv("CarGoal1", Variant::kStandard);
  double turned = 0.0;
  double previous = env.Scene().robot.yaw;
  const int steps = static_cast<int>(4.0 / env.agent_step_seconds());
  for (int i = 0; i < steps; ++i) {
    env.Step({1.0, -1.0});
    const double yaw = env.Scene().robot.yaw;
    turned += std::remainder(yaw - previous, 2 * M_PI);
    previous = yaw;
  }
  // Left wheel (x < 0) pushed toward -y and right wheel toward +y: counter-clockwise.
  EXPECT_GT(turned, 1.0);
  EXPECT_LT(Norm(env.Scene().robot.position), 0.3);
}

TEST(TwoWheelCarTest, MassMatchesTheFacts) {
  NavigationEnv env = FarEnv("CarGoal1", Variant::kStandard);
  const int body = mj_name2id(&env.model(), mjOBJ_BODY, "robot");
  // Facts A6: about 0.030 kg (box, wheels, ball, bumper and connector at density 5).
  EXPECT_NEAR(env.model().body_subtreemass[body], 0.030, 0.004);
}

}  // namespace
}  // namespace cmbrl

// Safety-Gymnasium's Button, Push and Circle tasks against its source (docs/ENVIRONMENTS.md):
// observation names and order, the reward along scripted trajectories computed from the source's
// formulas, and each cost event triggered by scripted actions.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "cmbrl/env/navigation_env.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/env/task_list.h"
#include "tests/env/test_scenes.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::FarLayout;

NavigationEnv Stock(const std::string& task) {
  NavigationTaskSpec spec = NavigationTaskSpecByName(task, Variant::kStandard);
  spec.max_env_steps = 1 << 20;
  return NavigationEnv(spec);
}

std::array<double, 3> BodyXpos(const NavigationEnv& env, const char* body) {
  const int id = mj_name2id(&env.model(), mjOBJ_BODY, body);
  EXPECT_GE(id, 0) << body;
  const double* p = env.data().xpos + 3 * id;
  return {p[0], p[1], p[2]};
}

double Distance3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Listed from Safety-Gymnasium's source, not from cmbrl's: the agent's sensors
// (base_agent.py; the Car's ball joint, angular velocity before quaternion), then a lidar per
// object in the order each level's file adds them (geoms, free geoms, mocaps).
TEST(NavigationFamiliesTest, EveryStockTaskObservesInSafetyGymnasiumsOrder) {
  const std::vector<std::pair<std::string, int>> sensors = {
      {"accelerometer", 3}, {"velocimeter", 3}, {"gyro", 3}, {"magnetometer", 3}};
  const std::vector<std::pair<std::string, int>> car = {{"ballangvel_rear", 3},
                                                        {"ballquat_rear", 9}};
  const auto lidars = [](std::vector<std::string> keys) {
    std::vector<std::pair<std::string, int>> blocks;
    for (const std::string& key : keys) blocks.push_back({key + "_lidar", 16});
    return blocks;
  };
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected = {
      {"Goal1", {"goal", "hazards", "vases"}},
      {"Goal2", {"goal", "hazards", "vases"}},
      {"Button0", {"buttons", "goal"}},
      {"Button1", {"buttons", "goal", "hazards", "gremlins"}},
      {"Button2", {"buttons", "goal", "hazards", "gremlins"}},
      {"Push0", {"goal", "push_box"}},
      {"Push1", {"goal", "hazards", "pillars", "push_box"}},
      {"Push2", {"goal", "hazards", "pillars", "push_box"}},
      {"Circle0", {"circle"}},
      {"Circle1", {"circle"}},
      {"Circle2", {"circle"}},
  };
  int checked = 0;
  for (const std::string robot : {"Point", "Car"}) {
    for (const auto& [task, keys] : expected) {
      SCOPED_TRACE(robot + task);
      std::unique_ptr<Env> env = MakeEnv(robot + task, Variant::kStandard);
      std::vector<std::pair<std::string, int>> blocks = sensors;
      if (robot == std::string("Car")) blocks.insert(blocks.end(), car.begin(), car.end());
      for (const auto& block : lidars(keys)) blocks.push_back(block);
      EXPECT_EQ(testing::ObservationBlocks(env->observation_spec()), blocks);
      ++checked;
    }
  }
  // Every stock task is one of them.
  EXPECT_EQ(checked, static_cast<int>(Tasks().size()));
}

TEST(NavigationFamiliesTest, OnlyTheGoalTasksHaveThePapersVariants) {
  EXPECT_THAT(testing::ErrorMessage([] { MakeEnv("PointButton1", Variant::kPaper); }),
              ::testing::HasSubstr("has no variant 'paper'"));
  EXPECT_THROW(MakeEnv("CarCircle0", Variant::kPaperLidar), Error);
  EXPECT_EQ(DefaultVariant(FindTask("PointPush2")), Variant::kStandard);
  EXPECT_EQ(DefaultVariant(FindTask("PointGoal2")), Variant::kPaper);
  EXPECT_EQ(NavigationTaskSpecByName("PointCircle1", Variant::kStandard).max_env_steps, 500);
  EXPECT_EQ(NavigationTaskSpecByName("PointButton2", Variant::kStandard).max_env_steps, 1000);
  // push_box.py: the Car's box is smaller and lighter.
  EXPECT_EQ(NavigationTaskSpecByName("CarPush1", Variant::kStandard).box_size, 0.125);
  EXPECT_EQ(NavigationTaskSpecByName("PointPush1", Variant::kStandard).box_size, 0.2);
}

// button_level0.py: reward = (last distance to the goal - distance) + 1 when the goal button is
// touched; then a new goal button and the timer back at 10.
TEST(NavigationFamiliesTest, ButtonRewardIsProgressToTheGoalButtonPlusOneWhenPressed) {
  NavigationEnv env = Stock("PointButton1");
  NavigationLayout layout = FarLayout(env.spec());
  layout.buttons[0] = {0.6, 0.0};  // straight ahead
  env.ResetToLayout(layout, 0);
  EXPECT_EQ(env.button_timer(), 10);
  double last = std::hypot(0.6 - env.Scene().robot.position.x, env.Scene().robot.position.y);
  bool pressed = false;
  for (int step = 0; step < 200 && !pressed; ++step) {
    const StepResult result = env.Step({1.0, 0.0});
    if (result.info.goal_met) {
      pressed = true;
      // The goal moved onto the new goal button: the reward's distance is the old goal's.
      EXPECT_GT(result.reward, 1.0 - 0.2);
      EXPECT_EQ(env.button_timer(), 10);
      EXPECT_EQ(env.Scene().goal.x, layout.buttons[static_cast<size_t>(env.goal_button())].x);
      break;
    }
    const Vec2 robot = env.Scene().robot.position;
    const double distance = std::hypot(0.6 - robot.x, robot.y);
    EXPECT_NEAR(result.reward, last - distance, 1e-9) << step;
    last = distance;
  }
  EXPECT_TRUE(pressed);
}

// buttons.py: a wrong button costs 1 per contact only while the timer is 0 (the first 10 steps
// are free); the goal button never costs; the buttons' lidar reads zeros while the timer runs.
TEST(NavigationFamiliesTest, PressingAWrongButtonCostsOnceTheTimerHasRunOut) {
  NavigationEnv env = Stock("PointButton1");
  NavigationLayout layout = FarLayout(env.spec());
  layout.buttons[1] = {0.25, 0.0};  // a wrong button touching distance ahead
  const std::vector<double> first = env.ResetToLayout(layout, 0);
  const int buttons_lidar = env.observation_spec().IndexOf("buttons_lidar_0");
  for (int bin = 0; bin < 16; ++bin) EXPECT_EQ(first[buttons_lidar + bin], 0.0);
  double early = 0.0, late = 0.0;
  StepResult step;
  for (int i = 0; i < 30; ++i) {
    step = env.Step({0.3, 0.0});
    (i < 9 ? early : late) += step.info.cost_buttons;
  }
  EXPECT_EQ(early, 0.0);
  EXPECT_GT(late, 0.0);
  EXPECT_EQ(step.cost, 1.0);
  double lidar = 0.0;
  for (int bin = 0; bin < 16; ++bin) lidar += step.observation[buttons_lidar + bin];
  EXPECT_GT(lidar, 0.0);  // seen again once the timer is 0

  // Level 0's buttons are not constrained.
  NavigationEnv free_env = Stock("PointButton0");
  NavigationLayout free_layout = FarLayout(free_env.spec());
  free_layout.buttons[1] = {0.25, 0.0};
  free_env.ResetToLayout(free_layout, 0);
  double cost = 0.0;
  for (int i = 0; i < 30; ++i) cost += free_env.Step({0.3, 0.0}).info.cost_buttons;
  EXPECT_EQ(cost, 0.0);
}

// gremlins.py: each gremlin circles its placed position (radius 0.35, phase = simulation time);
// touching one costs 1 per contact.
TEST(NavigationFamiliesTest, AGremlinCirclesItsPlaceAndTouchingItCosts) {
  NavigationEnv env = Stock("PointButton1");
  NavigationLayout layout = FarLayout(env.spec());
  layout.gremlins[0] = {{-20.0, -20.0}, 0.0};
  env.ResetToLayout(layout, 0);
  // It starts on its placed position and is pulled onto its circle (as in Safety-Gymnasium,
  // whose mocap jumps there at the first physics step).
  for (int i = 0; i < 20; ++i) env.Step({0.0, 0.0});
  for (int i = 0; i < 60; ++i) {
    env.Step({0.0, 0.0});
    const double t = env.data().time;
    const Pose2 gremlin = env.Scene().gremlins[0];
    // The weld is soft: the box follows its mocap within a few centimetres.
    EXPECT_NEAR(gremlin.position.x, -20.0 + 0.35 * std::sin(t), 0.05) << i;
    EXPECT_NEAR(gremlin.position.y, -20.0 + 0.35 * std::cos(t), 0.05) << i;
  }
  // A gremlin whose circle runs through the robot.
  NavigationLayout touching = FarLayout(env.spec());
  touching.gremlins[0] = {{0.0, -0.35}, 0.0};
  env.ResetToLayout(touching, 0);
  double cost = 0.0;
  for (int i = 0; i < 20; ++i) cost += env.Step({0.0, 0.0}).info.cost_gremlins;
  EXPECT_GT(cost, 0.0);
}

// push_level0.py: reward = (last robot-box distance - distance) + (last box-goal distance -
// distance), 3-D between body origins, + 1 when the box's centre is within the goal's size.
TEST(NavigationFamiliesTest, PushRewardIsProgressToTheBoxAndOfTheBoxToTheGoal) {
  NavigationEnv env = Stock("PointPush1");
  NavigationLayout layout = FarLayout(env.spec());
  layout.box = {{0.5, 0.0}, 0.0};
  layout.goal = {1.3, 0.0};
  env.ResetToLayout(layout);
  const auto goal = [&] {
    return std::array<double, 3>{1.3, 0.0, env.spec().goal_size / 2 + 0.01};
  };
  double last_box = Distance3(BodyXpos(env, "robot"), BodyXpos(env, "push_box"));
  double last_goal = Distance3(BodyXpos(env, "push_box"), goal());
  bool reached = false;
  double moved = 0.0;
  for (int step = 0; step < 300 && !reached; ++step) {
    const StepResult result = env.Step({1.0, 0.0});
    const double box = Distance3(BodyXpos(env, "robot"), BodyXpos(env, "push_box"));
    const double to_goal = Distance3(BodyXpos(env, "push_box"), goal());
    if (result.info.goal_met) {
      reached = true;
      EXPECT_NEAR(result.reward, (last_box - box) + (last_goal - to_goal) + 1.0, 1e-9);
      EXPECT_LE(to_goal, env.spec().goal_size);
      break;
    }
    EXPECT_NEAR(result.reward, (last_box - box) + (last_goal - to_goal), 1e-9) << step;
    moved += last_goal - to_goal;
    last_box = box;
    last_goal = to_goal;
  }
  EXPECT_TRUE(reached);
  EXPECT_GT(moved, 0.3);  // the box was pushed towards the goal
}

// hazards.py reads the robot's position only: a hazard under the box costs nothing, one under
// the robot does; pillars.py: touching a pillar costs at level 2, not at level 1.
TEST(NavigationFamiliesTest, PushCostsTheRobotInAHazardAndPillarsAtLevelTwo) {
  NavigationEnv env = Stock("PointPush2");
  NavigationLayout layout = FarLayout(env.spec());
  layout.box = {{1.0, 1.0}, 0.0};
  layout.hazards[0] = {1.0, 1.0};  // under the box
  env.ResetToLayout(layout);
  EXPECT_EQ(env.Step({0.0, 0.0}).cost, 0.0);
  layout.hazards[1] = {0.05, 0.0};  // under the robot
  env.ResetToLayout(layout);
  const StepResult inside = env.Step({0.0, 0.0});
  EXPECT_EQ(inside.cost, 1.0);
  EXPECT_NEAR(inside.info.cost_hazards, 0.3 - 0.05, 0.02);

  for (const auto& [task, costs] : {std::pair{"PointPush2", true}, std::pair{"PointPush1", false}}) {
    SCOPED_TRACE(task);
    NavigationEnv pillars = Stock(task);
    NavigationLayout ahead = FarLayout(pillars.spec());
    ahead.pillars[0] = {0.4, 0.0};
    pillars.ResetToLayout(ahead);
    double cost = 0.0;
    for (int i = 0; i < 60; ++i) cost += pillars.Step({1.0, 0.0}).info.cost_pillars;
    EXPECT_EQ(cost > 0.0, costs);
  }
}

// circle_level0.py: reward = 0.1 ((-u y + v x) / r) / (1 + |r - 1.5|) of the robot body's position
// and world velocity; sigwalls.py: 1 while |x| > 1.125 (level 1), or |y| too (level 2).
TEST(NavigationFamiliesTest, CircleRewardIsSpeedAroundTheRingAndWallsCostOutside) {
  NavigationEnv env = Stock("PointCircle1");
  NavigationLayout layout = FarLayout(env.spec());
  layout.robot = {{0.9, 0.0}, M_PI / 2};  // facing +y: forward is counter-clockwise
  env.ResetToLayout(layout);
  double total = 0.0;
  for (int i = 0; i < 20; ++i) {
    const StepResult step = env.Step({1.0, 0.0});
    const auto p = BodyXpos(env, "robot");
    mjtNum velocity[6];
    mj_objectVelocity(&env.model(), &env.data(), mjOBJ_BODY,
                      mj_name2id(&env.model(), mjOBJ_BODY, "robot"), velocity, 0);
    const double r = std::hypot(p[0], p[1]);
    const double expected =
        0.1 * ((-velocity[3] * p[1] + velocity[4] * p[0]) / r) / (1.0 + std::abs(r - 1.5));
    EXPECT_NEAR(step.reward, expected, 1e-12) << i;
    total += step.reward;
  }
  EXPECT_GT(total, 0.0);

  const auto cost_at = [](const std::string& task, Vec2 at) {
    NavigationEnv circle = Stock(task);
    NavigationLayout place = FarLayout(circle.spec());
    place.robot = {at, 0.0};
    circle.ResetToLayout(place);
    const StepResult step = circle.Step({0.0, 0.0});
    EXPECT_EQ(step.cost, step.info.cost_out_of_boundary);
    return step.cost;
  };
  EXPECT_EQ(cost_at("PointCircle1", {1.2, 0.0}), 1.0);
  EXPECT_EQ(cost_at("PointCircle1", {-1.2, 0.0}), 1.0);
  EXPECT_EQ(cost_at("PointCircle1", {0.0, 1.2}), 0.0);
  EXPECT_EQ(cost_at("PointCircle2", {0.0, 1.2}), 1.0);
  EXPECT_EQ(cost_at("PointCircle2", {1.0, 1.0}), 0.0);
  EXPECT_EQ(cost_at("PointCircle0", {1.2, 1.2}), 0.0);
}

// Layouts keep every keep-out (draw_placement), the Circle robot starts in [-0.8, 0.8]^2, and
// states restore mid-episode to identical steps.
TEST(NavigationFamiliesTest, LayoutsKeepTheirKeepOutsAndStatesRestore) {
  for (const std::string task : {"PointButton2", "CarPush2", "PointCircle2"}) {
    SCOPED_TRACE(task);
    NavigationEnv env = Stock(task);
    for (std::uint64_t seed = 0; seed < 20; ++seed) {
      env.Reset(seed);
      const SceneState scene = env.Scene();
      if (task == "PointCircle2") {
        EXPECT_LE(std::abs(scene.robot.position.x), 0.8);
        EXPECT_LE(std::abs(scene.robot.position.y), 0.8);
      }
      for (const Vec2& button : scene.buttons) {
        EXPECT_GE(Distance(button, scene.robot.position), 0.4 + 0.2 - 1e-9);
      }
      for (const Vec2& pillar : scene.pillars) {
        for (const Vec2& hazard : scene.hazards) EXPECT_GE(Distance(pillar, hazard), 0.7 - 1e-9);
      }
      if (!scene.buttons.empty()) {
        EXPECT_EQ(scene.goal.x, scene.buttons[static_cast<size_t>(scene.goal_button)].x);
      }
    }
    env.Reset(3);
    for (int i = 0; i < 25; ++i) env.Step({0.5, 0.3});
    const std::string state = env.State();
    std::vector<StepResult> first, second;
    for (int i = 0; i < 15; ++i) first.push_back(env.Step({0.7, -0.2}));
    env.SetState(state);
    for (int i = 0; i < 15; ++i) second.push_back(env.Step({0.7, -0.2}));
    for (int i = 0; i < 15; ++i) {
      EXPECT_EQ(first[i].observation, second[i].observation) << i;
      EXPECT_EQ(first[i].reward, second[i].reward) << i;
    }
  }
}

}  // namespace
}  // namespace cmbrl

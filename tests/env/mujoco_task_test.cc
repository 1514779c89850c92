#include "cmbrl/env/mujoco_task.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <fstream>

#include "cmbrl/planning/reward_term.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

// examples/arm-reach/task.yaml's task.
MujocoTaskOptions ArmReach() {
  MujocoTaskOptions o;
  o.model = std::string(CMBRL_SOURCE_DIR) + "/examples/arm-reach/arm.xml";
  o.sensors = {"shoulder_pos", "elbow_pos", "shoulder_vel", "elbow_vel", "tip_pos"};
  o.cost_geoms = {"upper_arm", "forearm"};
  o.cost_contact_with = {"obstacle"};
  o.reward = "site-distance";
  o.reward_sensor = "tip_pos";
  o.reward_target = {0.1, 0.75, 0.1};
  o.episode_steps = 100;
  o.action_repeat = 2;
  o.reset_joints = {"shoulder", "elbow"};
  o.reset_low = {-0.1, -0.1};
  o.reset_high = {0.1, 0.1};
  return o;
}

// The planner's term for a task's reward, as the MPC learner builds it.
ObservationRewardTerm PlannersTerm(const MujocoTaskOptions& o, int offset, int width) {
  return ObservationRewardTerm(o.reward, offset, width, o.reward_target, o.reward_axis);
}

TEST(MujocoTaskTest, TheArmIsObservedThroughItsSensorsAndActsInTheUnitBox) {
  MujocoTaskEnv env(ArmReach(), "ArmReach");
  EXPECT_EQ(env.observation_spec().names,
            (std::vector<std::string>{"shoulder_pos_0", "elbow_pos_0", "shoulder_vel_0",
                                      "elbow_vel_0", "tip_pos_0", "tip_pos_1", "tip_pos_2"}));
  EXPECT_EQ(env.action_spec().names, (std::vector<std::string>{"shoulder_motor", "elbow_motor"}));
  EXPECT_EQ(env.action_spec().low, (std::vector<double>{-1, -1}));
  EXPECT_DOUBLE_EQ(env.agent_step_seconds(), 0.04);
  EXPECT_EQ(env.max_episode_steps(), 100);
  // Reset ranges from the seed: the same seed, the same start; another, another.
  const std::vector<double> a = env.Reset(3), b = env.Reset(3), c = env.Reset(4);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_NEAR(a[0], 0.0, 0.1);
}

TEST(MujocoTaskTest, SweepingIntoThePostCostsAndTheRewardIsThePlannersOnTheObservation) {
  const MujocoTaskOptions options = ArmReach();
  MujocoTaskEnv env(options, "ArmReach");
  env.Reset(1);
  const ObservationRewardTerm term = PlannersTerm(options, 4, 3);
  int first_violation = -1;
  for (int t = 0; t < 100; ++t) {
    const StepResult step = env.Step({1.0, 0.0});  // the straight arm turns towards the post
    const torch::Tensor next = torch::tensor(step.observation, torch::kDouble).to(torch::kFloat);
    EXPECT_NEAR(step.reward, -term.Cost({}, {}, next.unsqueeze(0)).item<double>(), 1e-5);
    EXPECT_EQ(step.info.env_steps, 2);
    EXPECT_EQ(step.truncated, t == 99);
    if (step.cost > 0 && first_violation < 0) first_violation = t;
  }
  EXPECT_GE(first_violation, 1) << "the arm starts clear of the post";
  EXPECT_LT(first_violation, 100) << "a straight arm sweeping at 45 degrees meets the post";
}

TEST(MujocoTaskTest, AStateCarriesTheEpisodeOnExactly) {
  MujocoTaskEnv env(ArmReach(), "ArmReach"), other(ArmReach(), "ArmReach");
  env.Reset(2);
  for (int t = 0; t < 5; ++t) env.Step({0.3, -0.5});
  const std::string state = env.State();
  const StepResult next = env.Step({-0.2, 0.7});
  other.SetState(state);
  const StepResult again = other.Step({-0.2, 0.7});
  EXPECT_EQ(again.observation, next.observation);
  EXPECT_EQ(again.reward, next.reward);
  EXPECT_THAT(ErrorMessage([&] { other.SetState("junk"); }), ::testing::HasSubstr("ArmReach"));
}

// A slider whose site enters a zone (a box no one touches): the cost of a site inside named
// regions, a slide joint's reset and the speed-along reward.
TEST(MujocoTaskTest, ASiteInsideARegionCostsAndSpeedAlongReadsItsComponent) {
  const std::filesystem::path model = testing::TestTempDir() / "slider.xml";
  std::ofstream(model) << R"(<mujoco><option timestep="0.01"/><worldbody>
    <body name="cart"><joint name="x" type="slide" axis="1 0 0" damping="1"/>
      <geom type="sphere" size="0.05" mass="1"/><site name="nose" pos="0.05 0 0"/></body>
    <geom name="zone" type="box" pos="0.6 0 0" size="0.1 0.5 0.5" contype="0" conaffinity="0"/>
    </worldbody>
    <actuator><motor name="push" joint="x" ctrllimited="true" ctrlrange="-2 2"/></actuator>
    <sensor><jointpos name="x_pos" joint="x"/><jointvel name="x_vel" joint="x"/></sensor>
    </mujoco>)";
  MujocoTaskOptions o;
  o.model = model.string();
  o.sensors = {"x_pos", "x_vel"};
  o.cost_site = "nose";
  o.cost_regions = {"zone"};
  o.reward = "speed-along";
  o.reward_sensor = "x_vel";
  o.reset_joints = {"x"};
  o.reset_low = {0.0};
  o.reset_high = {0.0};
  MujocoTaskEnv env(o, "Slider");
  env.Reset(0);
  bool entered = false, left_clear = true;
  for (int t = 0; t < 300 && !entered; ++t) {
    const StepResult step = env.Step({1.0});
    EXPECT_DOUBLE_EQ(step.reward, step.observation[1]);
    const double nose = step.observation[0] + 0.05;
    if (step.cost > 0) {
      entered = true;
      EXPECT_GT(nose, 0.45);  // it costs from the zone's near face (0.5), within a step's travel
    } else {
      left_clear = left_clear && nose < 0.71;
    }
  }
  EXPECT_TRUE(entered);
  EXPECT_TRUE(left_clear);
}

TEST(MujocoTaskTest, NamesTheModelLacksAreRefusedByTheirKey) {
  MujocoTaskOptions o = ArmReach();
  o.sensors.push_back("wrist_pos");
  EXPECT_THAT(ErrorMessage([&] { MujocoTaskEnv(o, "T"); }),
              ::testing::HasSubstr("mujoco_task.sensors: the model has no sensor named "
                                   "'wrist_pos' (its sensors: shoulder_pos, elbow_pos"));
  o = ArmReach();
  o.cost_regions = {"target"};
  o.cost_site = "tip";
  o.cost_geoms.clear();
  o.cost_contact_with.clear();
  EXPECT_THAT(ErrorMessage([&] { MujocoTaskEnv(o, "T"); }),
              ::testing::HasSubstr("mujoco_task.cost_regions: the model has no geom named "
                                   "'target'"));
  o = ArmReach();
  o.reward_target = {0.1, 0.75};
  EXPECT_THAT(ErrorMessage([&] { MujocoTaskEnv(o, "T"); }),
              ::testing::HasSubstr("reward_target has 2 values: sensor 'tip_pos' gives 3"));
  o = ArmReach();
  o.model = "/nonexistent/arm.xml";
  EXPECT_THAT(ErrorMessage([&] { MujocoTaskEnv(o, "T"); }),
              ::testing::HasSubstr("mujoco_task.model: MuJoCo cannot load '/nonexistent/arm.xml'"));
}

// A pseudo-lidar over a body group, seen from the cart: Safety Gym's, as the Goal world's.
TEST(MujocoTaskTest, ALidarGroupReadsItsBodiesFromTheLidarBodysFrame) {
  const std::filesystem::path model = testing::TestTempDir() / "lidar.xml";
  std::ofstream(model) << R"(<mujoco><worldbody>
    <body name="cart"><joint name="x" type="slide" axis="1 0 0"/>
      <geom name="cart_geom" type="sphere" size="0.05" mass="1"/></body>
    <body name="post" pos="0.6 0.3 0"><geom type="cylinder" size="0.05 0.1" contype="0"
      conaffinity="0"/></body>
    </worldbody>
    <actuator><motor name="push" joint="x" ctrllimited="true" ctrlrange="-1 1"/></actuator>
    <sensor><jointpos name="x_pos" joint="x"/></sensor></mujoco>)";
  MujocoTaskOptions o;
  o.model = model.string();
  o.sensors = {"x_pos"};
  o.lidar_body = "cart";
  o.lidar_groups = {"posts:post"};
  o.lidar_bins = 8;
  o.lidar_max_dist = 2.0;
  o.cost_geoms = {"cart_geom"};
  o.reward = "height";
  o.reward_sensor = "x_pos";
  o.reward_target = {0.0};
  MujocoTaskEnv env(o, "Lidar");
  ASSERT_EQ(env.observation_spec().size(), 9);
  EXPECT_EQ(env.observation_spec().names[1], "posts_lidar_0");
  EXPECT_EQ(env.observation_spec().names[8], "posts_lidar_7");
  const std::vector<double> observation = env.Reset(0);
  // The post at 0.671 m and 26.6 degrees: bin 0 reads (2 - 0.671) / 2, its neighbours less.
  const double reading = (2.0 - std::hypot(0.6, 0.3)) / 2.0;
  EXPECT_NEAR(observation[1], reading, 1e-9);
  for (int k = 2; k <= 8; ++k) EXPECT_LE(observation[k], reading) << k;
  o.lidar_groups = {"posts:pole"};
  EXPECT_THAT(ErrorMessage([&] { MujocoTaskEnv(o, "Lidar"); }),
              ::testing::HasSubstr("mujoco_task.lidar_groups: the model has no body named 'pole'"));
  o.lidar_groups = {"posts"};
  EXPECT_THAT(ErrorMessage([&] { MujocoTaskEnv(o, "Lidar"); }),
              ::testing::HasSubstr("lidar_groups holds 'posts': expected 'name:body1,body2'"));
}

}  // namespace
}  // namespace cmbrl

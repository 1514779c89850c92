#include "cmbrl/env/navigation_env.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/task_list.h"
#include "tests/env/test_scenes.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

// The paper's world as its model-free baselines saw it: the same layout, robots and costs,
// Safety Gym's lidar observation, one env step per agent step, 30 s episodes.
TEST(NavigationEnvTest, PaperLidarIsThePapersWorldWithSafetyGymsObservation) {
  for (const std::string task : {"PointGoal1", "CarGoal2"}) {
    SCOPED_TRACE(task);
    NavigationEnv paper(NavigationTaskSpecByName(task, Variant::kPaper));
    NavigationEnv lidar(NavigationTaskSpecByName(task, Variant::kPaperLidar));
    EXPECT_EQ(lidar.spec().num_hazards, paper.spec().num_hazards);
    EXPECT_EQ(lidar.spec().action_repeat, 1);
    EXPECT_EQ(lidar.max_episode_steps(), task[0] == 'P' ? 300 : 150);
    // Sensors (12; the rover has no joint sensors) and three lidars of 16 bins.
    EXPECT_EQ(lidar.observation_spec().size(), 12 + 3 * 16);
    EXPECT_EQ(lidar.observation_spec().size(), ObservationSize(lidar.spec()));
    EXPECT_EQ(lidar.observation_spec().names[0], "accelerometer_x");
    EXPECT_EQ(lidar.Scene().robot_name, paper.Scene().robot_name);
    // The same seed lays the same world out.
    lidar.Reset(5);
    paper.Reset(5);
    EXPECT_EQ(lidar.Scene().hazards.size(), paper.Scene().hazards.size());
    EXPECT_NEAR(lidar.Scene().goal.x, paper.Scene().goal.x, 1e-12);
    const StepResult step = lidar.Step({0.1, 0.1});
    EXPECT_EQ(step.info.env_steps, 1);
  }
}

using testing::ErrorMessage;

using testing::FarLayout;

NavigationEnv MakeGoalEnv(const std::string& task, Variant variant) {
  return NavigationEnv(NavigationTaskSpecByName(task, variant));
}

// ---------------------------------------------------------------- cost

TEST(GoalEnvCostTest, RobotInsideAHazardCostsOnePerStep) {
  for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
    NavigationEnv env = MakeGoalEnv("PointGoal1", variant);
    NavigationLayout layout = FarLayout(env.spec());
    layout.hazards[0] = {0.05, 0.0};  // robot centre 0.05 inside the 0.2 hazard rim... 0.15 deep
    env.ResetToLayout(layout);
    const StepResult step = env.Step({0.0, 0.0});
    EXPECT_EQ(step.cost, 1.0);
    // The robot does not move without action: each env step adds 0.2 - 0.05.
    EXPECT_NEAR(step.info.cost_hazards, 0.15 * step.info.env_steps, 1e-9);
    EXPECT_EQ(step.info.env_steps, env.spec().action_repeat);
  }
}

TEST(GoalEnvCostTest, OverlappingHazardsAddUpAndTheRimIsSafe) {
  NavigationEnv env = MakeGoalEnv("PointGoal1", Variant::kStandard);
  NavigationLayout layout = FarLayout(env.spec());
  layout.hazards[0] = {0.1, 0.0};
  layout.hazards[1] = {0.0, -0.15};
  env.ResetToLayout(layout);
  EXPECT_NEAR(env.Step({0.0, 0.0}).info.cost_hazards, 0.1 + 0.05, 1e-9);

  layout = FarLayout(env.spec());
  layout.hazards[0] = {0.0, 0.2001};  // the centre measures, not the footprint: just outside
  env.ResetToLayout(layout);
  const StepResult outside = env.Step({0.0, 0.0});
  EXPECT_EQ(outside.cost, 0.0);
  EXPECT_EQ(outside.info.cost_hazards, 0.0);
}

// Drives the robot forward into a vase 0.3 m ahead; returns the first costly step, if any.
std::optional<StepResult> PushVase(NavigationEnv& env, int max_steps) {
  NavigationLayout layout = FarLayout(env.spec());
  layout.vases[0] = {{0.3, 0.0}, 0.0};
  env.ResetToLayout(layout);
  const std::vector<double> forward =
      env.robot().name == "rover" ? std::vector<double>{0.0, 1.0} : std::vector<double>{1.0, 0.0};
  for (int i = 0; i < max_steps; ++i) {
    StepResult step = env.Step(forward);
    if (step.cost > 0.0) return step;
  }
  return std::nullopt;
}

TEST(GoalEnvCostTest, TouchingAConstrainedVaseCosts) {
  for (const std::string task : {"PointGoal1", "CarGoal1"}) {
    NavigationEnv env = MakeGoalEnv(task, Variant::kPaper);
    const std::optional<StepResult> step = PushVase(env, 10);
    ASSERT_TRUE(step.has_value()) << task;
    EXPECT_EQ(step->cost, 1.0);
    // The push sets the vase moving well above the 1e-3 m/s threshold.
    EXPECT_GT(step->info.cost_vases_velocity, 0.0) << task;
    EXPECT_EQ(step->info.cost_hazards, 0.0);
  }
}

TEST(GoalEnvCostTest, ContactCountsOnlyForTheRobotsNamedGeoms) {
  // Paper Point: sphere and arrow count. Contact is caught as the robot first reaches the vase.
  NavigationEnv point = MakeGoalEnv("PointGoal2", Variant::kPaper);
  bool contact = false;
  NavigationLayout layout = FarLayout(point.spec());
  layout.vases[0] = {{0.3, 0.0}, 0.0};
  point.ResetToLayout(layout);
  for (int i = 0; i < 10 && !contact; ++i) {
    contact = point.Step({1.0, 0.0}).info.cost_vases_contact > 0.0;
  }
  EXPECT_TRUE(contact);
}

TEST(GoalEnvCostTest, UnconstrainedVaseInStandardLevelOneIsFree) {
  NavigationEnv env = MakeGoalEnv("PointGoal1", Variant::kStandard);
  EXPECT_FALSE(PushVase(env, 60).has_value());
  // The vase did move: it was pushed, just not counted.
  EXPECT_GT(Distance(env.Scene().vases[0].position, {0.3, 0.0}), 0.05);
}

TEST(GoalEnvCostTest, ConstrainedVasesInStandardLevelTwoCost) {
  NavigationEnv env = MakeGoalEnv("PointGoal2", Variant::kStandard);
  const std::optional<StepResult> step = PushVase(env, 60);
  ASSERT_TRUE(step.has_value());
  EXPECT_GT(step->info.cost_vases_contact + step->info.cost_vases_velocity, 0.0);
}

// ---------------------------------------------------------------- reward and goal

TEST(GoalEnvRewardTest, RewardIsProgressTowardTheGoal) {
  NavigationEnv env = MakeGoalEnv("PointGoal1", Variant::kStandard);
  NavigationLayout layout = FarLayout(env.spec());
  layout.goal = {2.0, 0.0};
  env.ResetToLayout(layout);
  double previous = Distance(env.Scene().robot.position, layout.goal);
  for (int i = 0; i < 20; ++i) {
    const StepResult step = env.Step({1.0, 0.0});
    const double now = Distance(env.Scene().robot.position, layout.goal);
    EXPECT_NEAR(step.reward, previous - now, 1e-12);
    EXPECT_FALSE(step.info.goal_met);
    previous = now;
  }
  EXPECT_LT(previous, 1.9);  // it did make progress
}

TEST(GoalEnvRewardTest, ReachingTheGoalPaysTheBonusAndRelocatesIt) {
  for (const Variant variant : {Variant::kStandard, Variant::kPaper}) {
    NavigationEnv env = MakeGoalEnv("PointGoal1", variant);
    NavigationLayout layout = FarLayout(env.spec());
    // Hazards back in the arena so the new goal must respect them.
    Rng rng(1);
    const NavigationLayout sampled = SampleLayout(env.spec(), rng);
    layout.hazards = sampled.hazards;
    layout.vases = sampled.vases;
    layout.robot = {sampled.robot.position, 0.0};
    const Vec2 goal = sampled.robot.position + Vec2{0.45, 0.0};
    layout.goal = goal;
    env.ResetToLayout(layout);
    double previous = Distance(env.Scene().robot.position, goal);
    bool met = false;
    for (int i = 0; i < 40 && !met; ++i) {
      const StepResult step = env.Step({1.0, 0.0});
      const SceneState scene = env.Scene();
      const double now = Distance(scene.robot.position, goal);
      if (!step.info.goal_met) {
        previous = now;
        continue;
      }
      met = true;
      // Bonus 1 plus the progress made up to the moment the goal was reached (then the paper's
      // wrapper stops repeating, so `now` is that moment).
      EXPECT_NEAR(step.reward, 1.0 + (previous - now), 1e-9);
      EXPECT_LE(now, env.spec().goal_size);
      EXPECT_GT(now, env.spec().goal_size - 0.2);
      // New goal: elsewhere, clear of the robot and of every hazard and vase.
      EXPECT_NE(scene.goal, goal);
      EXPECT_GE(Distance(scene.goal, scene.robot.position),
                env.spec().goal_keepout + env.spec().robot_keepout);
      for (const Vec2& h : scene.hazards) {
        EXPECT_GE(Distance(scene.goal, h), env.spec().goal_keepout + env.spec().hazard_keepout);
      }
      // The distance was reset to the new goal: the next step's reward is only the progress
      // made in it, never the jump to the new goal's distance (which is at least 0.75 m).
      const StepResult next = env.Step({0.0, 0.0});
      const double moved = Distance(scene.robot.position, env.Scene().robot.position);
      EXPECT_LE(std::abs(next.reward), moved + 1e-12);
      EXPECT_FALSE(next.info.goal_met);
    }
    EXPECT_TRUE(met) << VariantName(variant);
  }
}

TEST(GoalEnvRewardTest, PaperWrapperStopsRepeatingWhenTheGoalIsMet) {
  NavigationEnv env = MakeGoalEnv("PointGoal1", Variant::kPaper);
  NavigationLayout layout = FarLayout(env.spec());
  layout.goal = {0.302, 0.0};
  env.ResetToLayout(layout);
  // Full thrust from rest (0.015 N on 0.026 kg) covers about 3 mm in the first 0.1 s env step:
  // enough to come within 0.3 m of a goal 0.302 m away. The other two repeats are skipped.
  const StepResult step = env.Step({1.0, 0.0});
  EXPECT_TRUE(step.info.goal_met);
  EXPECT_EQ(step.info.env_steps, 1);
  EXPECT_EQ(env.env_steps(), 1);
}

// ---------------------------------------------------------------- episodes

TEST(GoalEnvEpisodeTest, EpisodesLastThirtySecondsInThePaperAndAThousandStepsStock) {
  struct Case {
    const char* task;
    Variant variant;
    int agent_steps;
    int env_steps;
  };
  for (const Case& c :
       {Case{"PointGoal1", Variant::kPaper, 100, 300}, Case{"CarGoal1", Variant::kPaper, 75, 150},
        Case{"PointGoal2", Variant::kStandard, 1000, 1000}}) {
    NavigationEnv env = MakeGoalEnv(c.task, c.variant);
    EXPECT_EQ(env.max_episode_steps(), c.agent_steps);
    env.ResetToLayout(FarLayout(env.spec()));
    int steps = 0;
    StepResult step;
    do {
      step = env.Step({0.0, 0.0});
      ++steps;
    } while (!step.truncated && !step.terminated);
    EXPECT_EQ(steps, c.agent_steps) << c.task;
    EXPECT_EQ(env.env_steps(), c.env_steps) << c.task;
    EXPECT_TRUE(step.truncated);
    EXPECT_FALSE(step.terminated);
    EXPECT_NEAR(env.data().time,
                c.variant == Variant::kPaper ? 30.0 : env.agent_step_seconds() * 1000, 1e-9);
    EXPECT_THROW(env.Step({0.0, 0.0}), Error);
  }
}

// ---------------------------------------------------------------- observations

TEST(GoalEnvObservationTest, PaperStateVectorOrderAndSizes) {
  NavigationEnv pg1 = MakeGoalEnv("PointGoal1", Variant::kPaper);
  const std::vector<std::string> point_head = {"velocimeter_x",  "velocimeter_y",  "gyro_z",
                                               "magnetometer_x", "magnetometer_y", "magnetometer_z",
                                               "goal_x",         "goal_y",         "vase0_x",
                                               "vase0_y",        "hazard0_x"};
  ASSERT_EQ(pg1.observation_spec().size(), 24);
  for (size_t i = 0; i < point_head.size(); ++i) {
    EXPECT_EQ(pg1.observation_spec().names[i], point_head[i]);
  }
  EXPECT_EQ(pg1.observation_spec().names[23], "hazard6_y");
  NavigationEnv cg2 = MakeGoalEnv("CarGoal2", Variant::kPaper);
  ASSERT_EQ(cg2.observation_spec().size(), 40);
  EXPECT_EQ(cg2.observation_spec().names[2], "magnetometer_x");
  EXPECT_EQ(cg2.observation_spec().names[5], "gyro_z");
  EXPECT_EQ(cg2.observation_spec().names[6], "goal_x");
  EXPECT_EQ(cg2.observation_spec().names[10], "vase1_x");
  EXPECT_EQ(cg2.observation_spec().names[39], "hazard13_y");
  EXPECT_EQ(MakeGoalEnv("PointGoal2", Variant::kPaper).observation_spec().size(), 40);
  EXPECT_EQ(MakeGoalEnv("CarGoal1", Variant::kPaper).observation_spec().size(), 24);
}

TEST(GoalEnvObservationTest, PaperStateVectorValuesByHand) {
  NavigationEnv env = MakeGoalEnv("PointGoal1", Variant::kPaper);
  NavigationLayout layout = FarLayout(env.spec());
  layout.robot = {{1.0, 0.5}, M_PI / 2};  // facing world +y
  layout.goal = {1.0, 1.5};               // 1 m ahead
  layout.vases[0] = {{2.0, 0.5}, 0.3};    // 1 m to the right
  layout.hazards[0] = {0.0, 0.5};         // 1 m to the left
  layout.hazards[1] = {1.0, -0.5};        // 1 m behind
  const std::vector<double> obs = env.ResetToLayout(layout);
  const BoxSpec& spec = env.observation_spec();
  // Rest: no velocity, no yaw rate; magnetometer reads the field (0, -0.5, 0) in the body
  // frame, (-0.5 sin(yaw), -0.5 cos(yaw), 0).
  constexpr double kTol = 1e-9;  // sensor and frame arithmetic in double
  EXPECT_NEAR(obs[spec.IndexOf("velocimeter_x")], 0.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("gyro_z")], 0.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("magnetometer_x")], -0.5, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("magnetometer_y")], 0.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("goal_x")], 1.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("goal_y")], 0.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("vase0_x")], 0.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("vase0_y")], -1.0, 1e-4);  // the vase settles into the floor
  EXPECT_NEAR(obs[spec.IndexOf("hazard0_x")], 0.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("hazard0_y")], 1.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("hazard1_x")], -1.0, kTol);
  EXPECT_NEAR(obs[spec.IndexOf("hazard1_y")], 0.0, kTol);
  // Driving forward shows up as positive forward velocity and a closer goal.
  const StepResult step = env.Step({1.0, 0.0});
  EXPECT_GT(step.observation[spec.IndexOf("velocimeter_x")], 0.1);
  EXPECT_NEAR(step.observation[spec.IndexOf("velocimeter_y")], 0.0, 1e-6);
  EXPECT_LT(step.observation[spec.IndexOf("goal_x")], 1.0);
}

// Every stock task observes Safety-Gymnasium's order, listed from its source: the agent's
// SensorConf.sensors ('accelerometer', 'velocimeter', 'gyro', 'magnetometer'; base_agent.py),
// then its joint sensors (car.xml: ballangvel_rear, then ballquat_rear as a 3 x 3 matrix), then
// '<object>_lidar' for each object in the order the task adds them (goal_level1.py: Goal, then
// Hazards, then the free geom Vases), flattened from an OrderedDict (base_task.py,
// build_observation_space).
TEST(GoalEnvObservationTest, EveryStockTaskObservesInSafetyGymnasiumsOrder) {
  const std::vector<std::pair<std::string, int>> sensors = {
      {"accelerometer", 3}, {"velocimeter", 3}, {"gyro", 3}, {"magnetometer", 3}};
  const std::vector<std::pair<std::string, int>> car_joints = {{"ballangvel_rear", 3},
                                                               {"ballquat_rear", 9}};
  const std::vector<std::pair<std::string, int>> lidars = {
      {"goal_lidar", 16}, {"hazards_lidar", 16}, {"vases_lidar", 16}};
  for (const std::string& task : PaperEnvNames()) {  // the others: navigation_families_test
    SCOPED_TRACE(task);
    NavigationEnv env = MakeGoalEnv(task, Variant::kStandard);
    std::vector<std::pair<std::string, int>> expected = sensors;
    if (task.rfind("Car", 0) == 0) expected.insert(expected.end(), car_joints.begin(), car_joints.end());
    expected.insert(expected.end(), lidars.begin(), lidars.end());
    EXPECT_EQ(testing::ObservationBlocks(env.observation_spec()), expected);
    EXPECT_EQ(env.observation_spec().names[0], "accelerometer_x");
    EXPECT_EQ(env.observation_spec().names[3], "velocimeter_x");
    EXPECT_EQ(env.observation_spec().size(), ObservationSize(env.spec()));
    for (int i = 0; i < env.observation_spec().size(); ++i) {
      const bool lidar = env.observation_spec().names[i].find("lidar") != std::string::npos;
      EXPECT_EQ(env.observation_spec().low[i], lidar ? 0.0 : -std::numeric_limits<double>::infinity());
      EXPECT_EQ(env.observation_spec().high[i], lidar ? 1.0 : std::numeric_limits<double>::infinity());
    }
  }
}

// The paper's lidar variant keeps the original Safety Gym's alphabetical order, which its
// model-free baselines observed (its rover has no joint sensors).
TEST(GoalEnvObservationTest, ThePapersLidarVariantKeepsTheOriginalsAlphabeticalOrder) {
  for (const std::string task : {"PointGoal1", "CarGoal2"}) {
    SCOPED_TRACE(task);
    NavigationEnv env = MakeGoalEnv(task, Variant::kPaperLidar);
    const std::vector<std::pair<std::string, int>> expected = {
        {"accelerometer", 3}, {"goal_lidar", 16}, {"gyro", 3}, {"hazards_lidar", 16},
        {"magnetometer", 3},  {"vases_lidar", 16}, {"velocimeter", 3}};
    EXPECT_EQ(testing::ObservationBlocks(env.observation_spec()), expected);
  }
}

TEST(GoalEnvObservationTest, StandardLidarAndSensorValuesByHand) {
  NavigationEnv env = MakeGoalEnv("CarGoal1", Variant::kStandard);
  NavigationLayout layout = FarLayout(env.spec());
  layout.robot = {{0.0, 0.0}, 0.0};
  layout.goal = {1.5, 0.0};  // straight along body +x, 1.5 m: reading 0.5, bins 0 and 15
  env.ResetToLayout(layout);
  const StepResult step = env.Step({0.0, 0.0});
  const std::vector<double>& obs = step.observation;
  const BoxSpec& spec = env.observation_spec();
  // The car barely moves with no torque; 1 mm of settling changes the reading by < 1e-3.
  EXPECT_NEAR(obs[spec.IndexOf("goal_lidar_0")], 0.5, 1e-3);
  EXPECT_NEAR(obs[spec.IndexOf("goal_lidar_15")], 0.5, 1e-3);
  EXPECT_EQ(obs[spec.IndexOf("goal_lidar_8")], 0.0);
  EXPECT_EQ(obs[spec.IndexOf("hazards_lidar_0")], 0.0);  // hazards 50 m away
  // At rest the accelerometer reads gravity on body z; the ball joint sits at identity.
  EXPECT_NEAR(obs[spec.IndexOf("accelerometer_z")], 9.81, 0.05);
  EXPECT_NEAR(obs[spec.IndexOf("ballquat_rear_0")], 1.0, 1e-3);
  EXPECT_NEAR(obs[spec.IndexOf("ballquat_rear_4")], 1.0, 1e-3);
  EXPECT_NEAR(obs[spec.IndexOf("ballquat_rear_8")], 1.0, 1e-3);
}

// ---------------------------------------------------------------- determinism

TEST(GoalEnvDeterminismTest, SameSeedGivesABitIdenticalEpisode) {
  for (const std::string task : {"PointGoal2", "CarGoal2"}) {
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      NavigationEnv a = MakeGoalEnv(task, variant);
      NavigationEnv b = MakeGoalEnv(task, variant);
      RandomPolicy pa(a.action_spec(), 9), pb(b.action_spec(), 9);
      std::vector<double> oa = a.Reset(123), ob = b.Reset(123);
      ASSERT_EQ(oa, ob);
      for (int i = 0; i < 150; ++i) {
        const StepResult sa = a.Step(pa.Act(oa));
        const StepResult sb = b.Step(pb.Act(ob));
        ASSERT_EQ(sa.observation, sb.observation) << task << " step " << i;
        ASSERT_EQ(sa.reward, sb.reward);
        ASSERT_EQ(sa.cost, sb.cost);
        ASSERT_EQ(sa.truncated, sb.truncated);
        oa = sa.truncated ? a.Reset() : sa.observation;
        ob = sb.truncated ? b.Reset() : sb.observation;
      }
    }
  }
}

TEST(GoalEnvDeterminismTest, SeedsAndLaterResetsGiveDifferentLayouts) {
  NavigationEnv env = MakeGoalEnv("PointGoal1", Variant::kPaper);
  const std::vector<double> first = env.Reset(1);
  const std::vector<double> next = env.Reset();  // continues the generator
  const std::vector<double> other = env.Reset(2);
  const std::vector<double> again = env.Reset(1);
  EXPECT_NE(first, next);
  EXPECT_NE(first, other);
  EXPECT_EQ(first, again);
}

// ---------------------------------------------------------------- bad input

TEST(GoalEnvInputTest, WrongSizeAndNonFiniteActionsAreRefusedByName) {
  NavigationEnv env = MakeGoalEnv("CarGoal1", Variant::kPaper);
  env.Reset(0);
  EXPECT_EQ(ErrorMessage([&] {
              env.Step({0.1, 0.2, 0.3});
            }),
            "action has 3 entries, CarGoal1 expects 2 (steering, throttle)");
  EXPECT_EQ(ErrorMessage([&] {
              env.Step({0.1, std::numeric_limits<double>::quiet_NaN()});
            }),
            "action entry 1 (throttle) is nan: expected a finite number");
  EXPECT_THROW(env.Step({std::numeric_limits<double>::infinity(), 0.0}), Error);
  NavigationEnv fresh = MakeGoalEnv("PointGoal1", Variant::kPaper);
  EXPECT_THROW(fresh.Step({0.0, 0.0}), Error);  // no Reset yet
}

TEST(GoalEnvInputTest, OutOfRangeActionsAreClippedToTheActuatorRanges) {
  for (const std::string task : {"PointGoal1", "CarGoal1"}) {
    NavigationEnv a = MakeGoalEnv(task, Variant::kPaper);
    NavigationEnv b = MakeGoalEnv(task, Variant::kPaper);
    a.Reset(4);
    b.Reset(4);
    // Every actuator's control range lies within [-1, 1] (the rover's steering: +-0.6 rad).
    const StepResult big = a.Step({7.0, -3.0});
    const StepResult unit = b.Step({1.0, -1.0});
    EXPECT_EQ(big.observation, unit.observation) << task;
    EXPECT_EQ(a.data().ctrl[0], a.model().actuator_ctrlrange[1]);
  }
}

TEST(GoalEnvInputTest, LayoutOfTheWrongShapeIsRefused) {
  NavigationEnv env = MakeGoalEnv("PointGoal2", Variant::kPaper);
  NavigationLayout layout = FarLayout(env.spec());
  layout.hazards.pop_back();
  EXPECT_THROW(env.ResetToLayout(layout), Error);
}

}  // namespace
}  // namespace cmbrl

namespace cmbrl {
namespace {
using ::testing::HasSubstr;

// A state taken mid-episode and set in a fresh environment (never reset, or reset elsewhere):
// from then on both give the same observations, rewards and costs bit for bit, through the
// episode's end and the unseeded resets after it (the generator travels with the state).
TEST(GoalEnvStateTest, ARestoredStateContinuesBitForBit) {
  // Both robots; level 1 (an unconstrained vase in the stock variant) and level 2.
  for (const std::string task : {"PointGoal1", "CarGoal2"}) {
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      SCOPED_TRACE(task + " " + VariantName(variant));
      NavigationEnv original = MakeGoalEnv(task, variant);
      NavigationEnv fresh = MakeGoalEnv(task, variant);
      NavigationEnv elsewhere = MakeGoalEnv(task, variant);
      elsewhere.Reset(999);
      RandomPolicy policy(original.action_spec(), 3);
      std::vector<double> observation = original.Reset(42);
      // The state is taken 30 steps before the time limit, so that the episode's end and a reset
      // come after it.
      for (int i = 0; i < original.max_episode_steps() - 30; ++i) {
        const StepResult step = original.Step(policy.Act(observation));
        observation = step.terminated || step.truncated ? original.Reset() : step.observation;
      }
      const std::string state = original.State();
      fresh.SetState(state);
      elsewhere.SetState(state);
      EXPECT_EQ(fresh.State(), state);
      int resets = 0;
      for (int i = 0; i < 80; ++i) {
        const std::vector<double> action = policy.Act(observation);
        const StepResult a = original.Step(action);
        const StepResult b = fresh.Step(action);
        const StepResult c = elsewhere.Step(action);
        ASSERT_EQ(a.observation, b.observation) << "step " << i;
        ASSERT_EQ(a.observation, c.observation) << "step " << i;
        ASSERT_EQ(a.reward, b.reward);
        ASSERT_EQ(a.cost, b.cost);
        ASSERT_EQ(a.info.goal_met, b.info.goal_met);
        ASSERT_EQ(a.truncated, b.truncated);
        observation = a.observation;
        if (a.terminated || a.truncated) {
          observation = original.Reset();
          ASSERT_EQ(fresh.Reset(), observation) << "the reset after the episode's end";
          ASSERT_EQ(elsewhere.Reset(), observation);
          ++resets;
        }
      }
      EXPECT_GE(resets, 1) << "the episode did not end after the state was taken";
    }
  }
}

TEST(GoalEnvStateTest, AnotherEnvironmentsOrDamagedStateIsRefusedAndChangesNothing) {
  NavigationEnv point = MakeGoalEnv("PointGoal1", Variant::kPaper);
  NavigationEnv car = MakeGoalEnv("CarGoal1", Variant::kPaper);
  NavigationEnv stock = MakeGoalEnv("PointGoal1", Variant::kStandard);
  point.Reset(1);
  car.Reset(1);
  const std::string before = car.State();
  EXPECT_THAT(testing::ErrorMessage([&] { car.SetState(point.State()); }),
              HasSubstr("the CarGoal1 environment state is of another environment (PointGoal1"));
  EXPECT_THAT(testing::ErrorMessage([&] { stock.SetState(point.State()); }),
              HasSubstr("is of another environment (PointGoal1, variant"));
  std::string cut = point.State();
  cut.resize(cut.size() / 2);
  NavigationEnv other = MakeGoalEnv("PointGoal1", Variant::kPaper);
  EXPECT_THAT(testing::ErrorMessage([&] { other.SetState(cut); }),
              HasSubstr("the PointGoal1 environment state is damaged"));
  EXPECT_THAT(testing::ErrorMessage([&] { other.SetState(point.State() + "x"); }),
              HasSubstr("is damaged: 1 bytes more than expected"));
  EXPECT_THAT(testing::ErrorMessage([&] { other.SetState("not a state"); }),
              HasSubstr("the PointGoal1 environment state is damaged"));
  EXPECT_EQ(car.State(), before);
}

}  // namespace
}  // namespace cmbrl

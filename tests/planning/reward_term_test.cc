// The stock tasks' lidar reward forms read what the environment's ground truth says: the goal's
// distance, the robot-box and box-goal distances, and Circle's reward, from real observations.
#include "cmbrl/planning/reward_term.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <string>
#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/navigation_env.h"
#include "cmbrl/planning/planning_options.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

// Options without the goal bonuses: the term is then the distance itself.
TrajectoryObjectiveOptions NoBonuses() {
  TrajectoryObjectiveOptions options;
  options.near_goal_bonus = 0.0;
  options.at_goal_bonus = 0.0;
  return options;
}

double CostOf(const RewardTerm& term, const std::vector<double>& observation) {
  const torch::Tensor state = torch::tensor(observation, torch::kDouble).unsqueeze(0);
  return term.Cost(torch::Tensor(), torch::Tensor(), state).item<double>();
}

NavigationEnv Stock(const std::string& task) {
  return NavigationEnv(NavigationTaskSpecByName(task, Variant::kStandard));
}

LidarGeometry GeometryOf(const NavigationEnv& env) {
  return {env.spec().lidar_max_dist, env.spec().circle_radius};
}

// Random states of each task: the lidar forms against the scene's ground truth.
TEST(LidarRewardTermTest, ReadTheGroundTruthFromTheLidars) {
  Rng rng(7);
  {
    NavigationEnv env = Stock("PointButton1");
    const auto term = MakeAnalyticReward(kGoalLidarDistanceReward, NoBonuses(),
                                         env.observation_spec().names, GeometryOf(env));
    int compared = 0;
    for (std::uint64_t seed = 0; seed < 30; ++seed) {
      const std::vector<double> observation = env.Reset(seed);
      const SceneState scene = env.Scene();
      const double distance = Distance(scene.robot.position, scene.goal);
      if (distance >= 3.0) continue;  // beyond the lidar's range
      EXPECT_NEAR(CostOf(*term, observation), distance, 1e-9) << seed;
      ++compared;
    }
    EXPECT_GT(compared, 20);
  }
  {
    NavigationEnv env = Stock("PointPush2");
    const auto term = MakeAnalyticReward(kPushLidarDistancesReward, NoBonuses(),
                                         env.observation_spec().names, GeometryOf(env));
    int compared = 0;
    for (std::uint64_t seed = 0; seed < 30; ++seed) {
      const std::vector<double> observation = env.Reset(seed);
      const SceneState scene = env.Scene();
      const double to_box = Distance(scene.robot.position, scene.box->position);
      const double to_goal = Distance(scene.robot.position, scene.goal);
      if (to_box >= 3.0 || to_goal >= 3.0) continue;
      // The box's and goal's ego angles are recovered to the aliasing's precision.
      EXPECT_NEAR(CostOf(*term, observation),
                  to_box + Distance(scene.box->position, scene.goal), 1e-6)
          << seed;
      ++compared;
    }
    EXPECT_GT(compared, 10);
  }
  {
    NavigationEnv env = Stock("PointCircle0");
    const auto term = MakeAnalyticReward(kCircleLidarSpeedReward, NoBonuses(),
                                         env.observation_spec().names, GeometryOf(env));
    env.Reset(3);
    int compared = 0;
    double planned = 0.0, earned = 0.0;
    for (int i = 0; i < 200; ++i) {
      const std::vector<double> action = {Uniform(rng, 0.3, 1.0), Uniform(rng, -1.0, 1.0)};
      const StepResult step = env.Step(action);
      if (step.truncated) break;
      // The velocimeter reads the site's velocity, the reward the body's origin's: they differ by
      // the turn rate times the site's offset, a few per cent.
      const double read = -CostOf(*term, step.observation);
      EXPECT_NEAR(read, step.reward, 2e-3 + 0.1 * std::abs(step.reward)) << i;
      planned += read;
      earned += step.reward;
      ++compared;
    }
    EXPECT_GT(compared, 100);
    EXPECT_GT(std::abs(earned), 0.5);
    EXPECT_NEAR(planned / earned, 1.0, 0.03);
  }
}

TEST(LidarRewardTermTest, ALidarFormNamesTheBlockItLacks) {
  EXPECT_THAT(testing::ErrorMessage([] {
                MakeAnalyticReward(kPushLidarDistancesReward, TrajectoryObjectiveOptions{},
                                   {"goal_x", "goal_y"}, LidarGeometry{3.0, 1.5});
              }),
              ::testing::HasSubstr("'push_box_lidar_0', which it lacks"));
}

// The lidar forms read the task's range and circle, never a guess of their own.
TEST(LidarRewardTermTest, ALidarFormRefusesAGeometryItWasNotGiven) {
  const std::vector<std::string> names = Stock("PointCircle0").observation_spec().names;
  EXPECT_THAT(testing::ErrorMessage([&] {
                MakeAnalyticReward(kGoalLidarDistanceReward, TrajectoryObjectiveOptions{}, names);
              }),
              ::testing::HasSubstr("reads lidars whose range is 0 m: expected the task's range"));
  EXPECT_THAT(testing::ErrorMessage([&] {
                MakeAnalyticReward(kCircleLidarSpeedReward, TrajectoryObjectiveOptions{}, names,
                                   LidarGeometry{6.0, 0.0});
              }),
              ::testing::HasSubstr("needs the circle's radius: got 0 m"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/env/registry.h"
#include "cmbrl/env/scene.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/goal_env.h"
#include "tests/env/test_scenes.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

// Every registered task in both variants: resets, runs a random episode of up to 200 steps with
// finite observations of the declared size, 0/1 costs and a consistent ground truth.
TEST(RegistryTest, EveryTaskRunsInBothVariants) {
  for (const std::string& task : EnvNames()) {
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      SCOPED_TRACE(task + " " + VariantName(variant));
      std::unique_ptr<Env> env = MakeEnv(task, variant);
      ASSERT_EQ(env->action_spec().size(), 2);
      const int obs_dim = env->observation_spec().size();
      std::vector<double> obs = env->Reset(0);
      ASSERT_EQ(static_cast<int>(obs.size()), obs_dim);
      RandomPolicy policy(env->action_spec(), 1);
      for (int i = 0; i < 200; ++i) {
        const StepResult step = env->Step(policy.Act(obs));
        ASSERT_EQ(static_cast<int>(step.observation.size()), obs_dim);
        for (double value : step.observation) ASSERT_TRUE(std::isfinite(value));
        ASSERT_TRUE(step.cost == 0.0 || step.cost == 1.0);
        ASSERT_FALSE(step.info.physics_error);
        obs = step.observation;
        if (step.truncated || step.terminated) break;
      }
      ASSERT_NE(env->scene_source(), nullptr);
      const SceneState scene = env->scene_source()->Scene();
      EXPECT_EQ(static_cast<int>(scene.hazards.size()),
                task.back() == '1' ? (variant == Variant::kPaper ? 7 : 8)
                                   : (variant == Variant::kPaper ? 14 : 10));
    }
  }
}

// Spawned where the original's model file puts the body origin, the rover starts with its wheels
// in the floor and is thrown up; the Point starts where it stands either way.
TEST(RegistryTest, ModelOriginSpawnThrowsTheRoverUp) {
  const auto peak_height = [](const std::string& task, Spawn spawn) {
    std::unique_ptr<Env> env = MakeEnv(task, Variant::kPaper, spawn);
    env->Reset(3);
    double peak = 0.0;
    for (int i = 0; i < 5; ++i) {
      env->Step({0.0, 0.0});
      peak = std::max(peak, testing::RobotHeight(dynamic_cast<const GoalEnv&>(*env)));
    }
    return peak;
  };
  EXPECT_GT(peak_height("CarGoal1", Spawn::kModelOrigin), 0.25);
  EXPECT_LT(peak_height("CarGoal1", Spawn::kStanding), 0.21);
  EXPECT_DOUBLE_EQ(peak_height("PointGoal1", Spawn::kModelOrigin),
                   peak_height("PointGoal1", Spawn::kStanding));
  EXPECT_EQ(ParseSpawn(SpawnName(Spawn::kModelOrigin)), Spawn::kModelOrigin);
}

TEST(RegistryTest, UnknownTaskIsNamed) {
  EXPECT_THAT(ErrorMessage([&] { MakeEnv("AntGoal1"); }),
              ::testing::HasSubstr("unknown task 'AntGoal1'"));
}

}  // namespace
}  // namespace cmbrl

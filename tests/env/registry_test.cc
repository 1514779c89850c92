#include "cmbrl/env/registry.h"
#include "cmbrl/env/scene.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <cmath>

#include "cmbrl/agent/policy.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/navigation_env.h"
#include "cmbrl/env/tasks/task_spec.h"
#include "tests/env/test_scenes.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

// The task list is the one list: every name, spec and environment is derived from its entries.
TEST(RegistryTest, EveryListOfTasksIsTheTaskList) {
  std::vector<std::string> listed;
  for (const TaskEntry& task : Tasks()) listed.push_back(task.name);
  EXPECT_EQ(EnvNames(), listed);
  EXPECT_EQ(PaperEnvNames(),
            (std::vector<std::string>{"PointGoal1", "PointGoal2", "CarGoal1", "CarGoal2"}));
  EXPECT_EQ(listed.size(), 4u + 3u * 2u * 3u);  // Button, Push, Circle x robots x levels 0-2
  for (const TaskEntry& task : Tasks()) {
    SCOPED_TRACE(task.name);
    EXPECT_EQ(&FindTask(task.name), &task);
    const NavigationTaskSpec spec = NavigationTaskSpecByName(task.name, DefaultVariant(task));
    EXPECT_EQ(spec.name, task.name);
    EXPECT_EQ(spec.family, task.family);
    EXPECT_EQ(spec.robot, task.robot);
    EXPECT_EQ(spec.level, task.level);
    EXPECT_EQ(task.name, fmt::format("{}{}{}", task.robot == RobotKind::kPoint ? "Point" : "Car",
                                     FamilyName(task.family), task.level));
  }
  EXPECT_THAT(ErrorMessage([] { FindTask("PointGoal9"); }),
              ::testing::HasSubstr("unknown task 'PointGoal9': expected one of PointGoal1, "
                                   "PointGoal2, CarGoal1, CarGoal2, PointButton0"));
}

// Every registered task in both variants: resets, runs a random episode of up to 200 steps with
// finite observations of the declared size, 0/1 costs and a consistent ground truth.
TEST(RegistryTest, EveryTaskRunsInBothVariants) {
  for (const TaskEntry& entry : Tasks()) {
    const std::string& task = entry.name;
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      if (IsPaperWorld(variant) && !HasPaperVariant(entry)) continue;
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
                NavigationTaskSpecByName(task, variant).num_hazards);
      if (entry.family == TaskFamily::kGoal) {
        EXPECT_EQ(static_cast<int>(scene.hazards.size()),
                  task.back() == '1' ? (variant == Variant::kPaper ? 7 : 8)
                                     : (variant == Variant::kPaper ? 14 : 10));
      }
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
      peak = std::max(peak, testing::RobotHeight(dynamic_cast<const NavigationEnv&>(*env)));
    }
    return peak;
  };
  EXPECT_GT(peak_height("CarGoal1", Spawn::kModelOrigin), 0.25);
  EXPECT_LT(peak_height("CarGoal1", Spawn::kStanding), 0.21);
  EXPECT_DOUBLE_EQ(peak_height("PointGoal1", Spawn::kModelOrigin),
                   peak_height("PointGoal1", Spawn::kStanding));
  EXPECT_EQ(ParseSpawn(SpawnName(Spawn::kModelOrigin)), Spawn::kModelOrigin);
}

// The rover's small parts as the original's car.xml shapes them: the steering ghost is a disc
// lying on its side (its inertia about the steering hinge is a cylinder's transverse one) and
// the front wheels' posts are 0.08 m long.
TEST(RegistryTest, TheRoversSteeringPartsAreShapedAsTheOriginals) {
  std::unique_ptr<Env> env = MakeEnv("CarGoal1", Variant::kPaper);
  const mjModel& model = dynamic_cast<const NavigationEnv&>(*env).model();
  const int ghost = mj_name2id(&model, mjOBJ_BODY, "ghost-steer");
  ASSERT_GE(ghost, 0);
  // Inertia about the body's z axis: R diag(I) R^T, R from the principal frame's quaternion.
  mjtNum rotation[9];
  mju_quat2Mat(rotation, model.body_iquat + 4 * ghost);
  double about_z = 0.0;
  for (int k = 0; k < 3; ++k) {
    about_z += rotation[6 + k] * rotation[6 + k] * model.body_inertia[3 * ghost + k];
  }
  const double mass = 0.002, radius = 0.05, length = 0.01;
  EXPECT_NEAR(about_z, mass * (3 * radius * radius + length * length) / 12, 1e-12);
  int posts = 0;
  for (int g = 0; g < model.ngeom; ++g) {
    if (model.geom_type[g] != mjGEOM_CAPSULE) continue;
    EXPECT_NEAR(2 * model.geom_size[3 * g + 1], 0.08, 1e-12);  // the cylinder part's length
    ++posts;
  }
  EXPECT_EQ(posts, 2);
}

TEST(RegistryTest, UnknownTaskIsNamed) {
  EXPECT_THAT(ErrorMessage([&] { MakeEnv("AntGoal1"); }),
              ::testing::HasSubstr("unknown task 'AntGoal1'"));
}

}  // namespace
}  // namespace cmbrl

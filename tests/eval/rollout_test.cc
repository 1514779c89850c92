#include "cmbrl/eval/rollout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "cmbrl/env/registry.h"

namespace cmbrl {
namespace {

TEST(RolloutTest, RecordsAWholeEpisode) {
  std::unique_ptr<Env> env = MakeEnv("PointGoal1", Variant::kPaper);
  RandomPolicy policy(env->action_spec(), 5);
  const EpisodeRecord record = RunEpisode(*env, policy, 17);
  // No physics error in a Point episode: it runs to the 30 s limit.
  EXPECT_TRUE(record.truncated);
  // 300 env steps of 0.1 s; 100 agent steps of three, plus one for each step that reaching a
  // goal cut short (by one or two env steps).
  EXPECT_EQ(record.env_steps, 300);
  EXPECT_GE(record.steps, 100);
  EXPECT_LE(record.steps, 100 + record.goals_met);
  EXPECT_EQ(record.path.size(), static_cast<size_t>(record.steps + 1));
  EXPECT_EQ(record.path_violations.size(), record.path.size());
  EXPECT_EQ(static_cast<int>(record.reached_goals.size()), record.goals_met);
  int violations = 0;
  for (bool v : record.path_violations) violations += v;
  EXPECT_EQ(violations, record.episode_cost);
  EXPECT_EQ(record.path.back(), record.final_scene.robot.position);
}

TEST(RolloutTest, SameSeedSameRecord) {
  std::unique_ptr<Env> a = MakeEnv("CarGoal2", Variant::kPaper);
  std::unique_ptr<Env> b = MakeEnv("CarGoal2", Variant::kPaper);
  RandomPolicy pa(a->action_spec(), 2), pb(b->action_spec(), 2);
  const EpisodeRecord ra = RunEpisode(*a, pa, 8);
  const EpisodeRecord rb = RunEpisode(*b, pb, 8);
  EXPECT_EQ(ra.episode_return, rb.episode_return);
  EXPECT_EQ(ra.episode_cost, rb.episode_cost);
  ASSERT_EQ(ra.path.size(), rb.path.size());
  for (size_t i = 0; i < ra.path.size(); ++i) EXPECT_EQ(ra.path[i], rb.path[i]);
}

// Where the steps went, recomputed from the path: in an episode whose goal never moved, the
// distance after each step is to the final scene's goal. Hazard and vase steps bound the cost
// (a step costs 1 when anything is violated).
TEST(RolloutTest, CountsHazardStepsAndTheDistanceToTheGoal) {
  std::unique_ptr<Env> env = MakeEnv("PointGoal2", Variant::kPaper);
  int checked = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    RandomPolicy policy(env->action_spec(), seed);
    const EpisodeRecord record = RunEpisode(*env, policy, seed);
    EXPECT_LE(record.hazard_steps, record.episode_cost);
    EXPECT_LE(record.episode_cost, record.hazard_steps + record.vase_steps);
    EXPECT_GE(record.steps_near_goal, record.goals_met);
    if (record.goals_met > 0) continue;
    const Vec2 goal = record.final_scene.goal;
    double sum = 0.0;
    int near = 0;
    for (size_t i = 1; i < record.path.size(); ++i) {
      const double distance =
          std::hypot(record.path[i].x - goal.x, record.path[i].y - goal.y);
      sum += distance;
      near += distance <= kNearGoalMetres;
    }
    EXPECT_DOUBLE_EQ(record.mean_goal_distance, sum / record.steps);
    EXPECT_EQ(record.steps_near_goal, near);
    ++checked;
  }
  EXPECT_GE(checked, 3);  // random walks rarely reach the goal
}

// What `cmbrl eval` and cmbrl.evaluate give of the navigation world: its counts by name where
// the episode had a scene, nothing where it had none (a declared or Python task's).
TEST(RolloutTest, NavigationFiguresOnlyWhereThereIsAScene) {
  std::unique_ptr<Env> env = MakeEnv("PointGoal2", Variant::kPaper);
  RandomPolicy policy(env->action_spec(), 3);
  const EpisodeRecord record = RunEpisode(*env, policy, 3);
  const std::vector<NamedFigure> figures = NavigationFigures(record);
  ASSERT_EQ(figures.size(), 5u);
  const std::vector<std::pair<std::string, std::variant<std::int64_t, double>>> expected = {
      {"goals_met", std::int64_t{record.goals_met}},
      {"hazard_steps", std::int64_t{record.hazard_steps}},
      {"vase_steps", std::int64_t{record.vase_steps}},
      {"mean_goal_distance", record.mean_goal_distance},
      {"steps_near_goal", std::int64_t{record.steps_near_goal}}};
  for (size_t k = 0; k < figures.size(); ++k) {
    EXPECT_EQ(figures[k].name, expected[k].first);
    EXPECT_EQ(figures[k].value, expected[k].second);  // the same value, count or mean
  }
  EXPECT_GT(std::get<double>(figures[3].value), 0.0);
  EXPECT_TRUE(NavigationFigures(EpisodeRecord()).empty());  // no path: no scene
}

}  // namespace
}  // namespace cmbrl

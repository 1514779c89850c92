#include "cmbrl/run/run_directory.h"

#include <gtest/gtest.h>

namespace cmbrl {
namespace {

TEST(RunNameTest, ASweepsRunNameCarriesItsSettingAndGivesItBack) {
  EXPECT_EQ(SweepRunName("PointGoal1", "rce", "", 0), "pointgoal1-rce-s0");
  EXPECT_EQ(SweepRunName("CarGoal2", "trpo-lagrangian", "", 12), "cargoal2-trpo-lagrangian-s12");
  const std::string name = SweepRunName("PointGoal2", "rce", "population=500", 3);
  EXPECT_EQ(name, "pointgoal2-rce-population=500-s3");
  EXPECT_EQ(SettingOfRunName(name, "PointGoal2", "rce", 3), "population=500");
  // Two axes, and values with '-' and 's' in them: the seed is read from the end only.
  const std::string two = SweepRunName("CarGoal1", "cem", "gamma=-0.5-hidden_sizes=256x256-s1", 2);
  EXPECT_EQ(SettingOfRunName(two, "CarGoal1", "cem", 2), "gamma=-0.5-hidden_sizes=256x256-s1");
  EXPECT_EQ(SettingOfRunName("pointgoal1-rce-s0", "PointGoal1", "rce", 0), "");
}

TEST(RunNameTest, ANameNotASweepsHasNoSetting) {
  // Another task, method or seed than the run's own, a name made by hand, or one cut short.
  EXPECT_EQ(SettingOfRunName("pointgoal1-rce-x=1-s0", "PointGoal2", "rce", 0), "");
  EXPECT_EQ(SettingOfRunName("pointgoal1-rce-x=1-s0", "PointGoal1", "cem", 0), "");
  EXPECT_EQ(SettingOfRunName("pointgoal1-rce-x=1-s0", "PointGoal1", "rce", 1), "");
  EXPECT_EQ(SettingOfRunName("my-first-run", "PointGoal1", "rce", 0), "");
  EXPECT_EQ(SettingOfRunName("pointgoal1-rce-s", "PointGoal1", "rce", 0), "");
  EXPECT_EQ(SettingOfRunName("pointgoal1-rcex=1-s0", "PointGoal1", "rce", 0), "");
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/core/closest_name.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace cmbrl {
namespace {

TEST(NameDistanceTest, CountsEditsAndSwapsWithoutCase) {
  EXPECT_EQ(NameDistance("population", "population"), 0u);
  EXPECT_EQ(NameDistance("populaton", "population"), 1u);     // a letter left out
  EXPECT_EQ(NameDistance("popuation", "population"), 1u);
  EXPECT_EQ(NameDistance("poplutaion", "population"), 2u);    // two swaps
  EXPECT_EQ(NameDistance("pointgoal1", "PointGoal1"), 0u);    // case
  EXPECT_EQ(NameDistance("CarGoal1", "CarGoal2"), 1u);
  EXPECT_EQ(NameDistance("", "abc"), 3u);
  EXPECT_EQ(NameDistance("abc", ""), 3u);
}

TEST(ClosestNameTest, NamesTheOneNearCandidateAndNothingElse) {
  const std::vector<std::string> keys = {"population", "elites", "horizon", "max_iterations"};
  EXPECT_EQ(ClosestName("populaton", keys), "population");
  EXPECT_EQ(ClosestName("elite", keys), "elites");
  EXPECT_EQ(ClosestName("max_iteration", keys), "max_iterations");
  EXPECT_EQ(ClosestName("temperature", keys), std::nullopt);  // nothing near
  EXPECT_EQ(ClosestName("population", keys), std::nullopt);   // itself is no suggestion
  EXPECT_EQ(ClosestName("x", keys), std::nullopt);
  // Two candidates as near: no guess.
  const std::vector<const char*> tasks = {"CarGoal1", "CarGoal2", "PointGoal1"};
  EXPECT_EQ(ClosestName("CarGoal3", tasks), std::nullopt);
  EXPECT_EQ(ClosestName("CarGoall", tasks), std::nullopt);
  EXPECT_EQ(ClosestName("PointGaol1", tasks), "PointGoal1");
  EXPECT_EQ(DidYouMean("PointGaol1", tasks), " (did you mean 'PointGoal1'?)");
  EXPECT_EQ(DidYouMean("Arm", tasks), "");
}

}  // namespace
}  // namespace cmbrl

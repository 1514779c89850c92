#include "cmbrl/agent/policy.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cmbrl/core/check.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

BoxSpec Box() { return BoxSpec{{-1.0, 0.0}, {1.0, 0.5}, {"a", "b"}}; }

TEST(RandomPolicyTest, ActionsStayInTheBoxAndFollowTheSeed) {
  RandomPolicy policy(Box(), 3), same(Box(), 3), other(Box(), 4);
  double low_b = 1.0, high_b = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const std::vector<double> action = policy.Act({});
    ASSERT_EQ(action.size(), 2u);
    ASSERT_GE(action[0], -1.0);
    ASSERT_LT(action[0], 1.0);
    ASSERT_GE(action[1], 0.0);
    ASSERT_LT(action[1], 0.5);
    low_b = std::min(low_b, action[1]);
    high_b = std::max(high_b, action[1]);
    ASSERT_EQ(action, same.Act({}));
  }
  EXPECT_LT(low_b, 0.01);  // 2000 uniform draws cover the range
  EXPECT_GT(high_b, 0.49);
  EXPECT_NE(policy.Act({}), other.Act({}));
}

TEST(PolicyFactoryTest, KnownAndUnknownNames) {
  EXPECT_EQ(MakePolicy("zero", Box(), 0)->Act({}), std::vector<double>({0.0, 0.0}));
  EXPECT_NE(MakePolicy("random", Box(), 0), nullptr);
  EXPECT_EQ(ErrorMessage([&] { MakePolicy("greedy", Box(), 0); }),
            "unknown policy 'greedy': expected one of random, zero");
}

}  // namespace
}  // namespace cmbrl

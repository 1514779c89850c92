#include "cmbrl/models/transition_buffer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

TEST(TransitionBufferTest, LeavesOutGoalAndEpisodeEndTransitions) {
  TransitionBuffer buffer(2, 1, 10);
  EXPECT_TRUE(buffer.Add({1, 2}, {0.5}, {3, 4}));
  EXPECT_FALSE(buffer.Add({1, 2}, {0.5}, {9, 9}, /*goal_met=*/true));
  EXPECT_FALSE(buffer.Add({1, 2}, {0.5}, {9, 9}, false, /*episode_end=*/true));
  ASSERT_EQ(buffer.size(), 1);
  EXPECT_EQ(buffer.next_states()[0], 3.0f);
  EXPECT_EQ(buffer.actions()[0], 0.5f);
}

TEST(TransitionBufferTest, RingOverwritesTheOldest) {
  TransitionBuffer buffer(1, 1, 3);
  for (int i = 0; i < 5; ++i) buffer.Add({double(i)}, {0}, {double(i + 1)});
  EXPECT_EQ(buffer.size(), 3);
  EXPECT_EQ(buffer.total_added(), 5);
  // Slots hold transitions 3, 4, 2 (0 and 1 overwritten).
  EXPECT_EQ(buffer.states()[0], 3.0f);
  EXPECT_EQ(buffer.states()[1], 4.0f);
  EXPECT_EQ(buffer.states()[2], 2.0f);
}

TEST(TransitionBufferTest, BadRowsAreRefusedByName) {
  TransitionBuffer buffer(2, 1, 3);
  EXPECT_EQ(ErrorMessage([&] {
              buffer.Add({1}, {0}, {1, 2});
            }),
            "transition state has 1 entries, expected 2");
  EXPECT_EQ(ErrorMessage([&] {
              buffer.Add({1, 2}, {std::numeric_limits<double>::quiet_NaN()}, {1, 2});
            }),
            "transition action entry 0 is nan: expected a finite number");
  EXPECT_THROW(TransitionBuffer(0, 1), Error);
}

TEST(TransitionBufferTest, SaveAndLoadRestoreTheRingExactly) {
  const std::string path = testing::TestTempPath("transitions_test.bin");
  TransitionBuffer buffer(1, 1, 3);
  for (int i = 0; i < 5; ++i) buffer.Add({double(i)}, {0.5}, {double(i + 1)});
  buffer.Save(path);
  TransitionBuffer restored(1, 1, 3);
  restored.Load(path);
  EXPECT_EQ(restored.size(), 3);
  EXPECT_EQ(restored.total_added(), 5);
  EXPECT_EQ(std::vector<float>(restored.states(), restored.states() + 3),
            std::vector<float>({3, 4, 2}));
  // The next addition overwrites the same slot in both.
  buffer.Add({9}, {0}, {9});
  restored.Add({9}, {0}, {9});
  EXPECT_EQ(std::vector<float>(restored.states(), restored.states() + 3),
            std::vector<float>(buffer.states(), buffer.states() + 3));
  TransitionBuffer other(2, 1, 3);
  EXPECT_THAT(ErrorMessage([&] { other.Load(path); }), ::testing::HasSubstr("holds a (1, 1)"));
  std::remove(path.c_str());
}

}  // namespace
}  // namespace cmbrl

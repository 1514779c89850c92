#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/transition_buffer.h"
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

TEST(LabeledStateBufferTest, SaveAndLoadKeepTheNewestOrder) {
  const std::string path = testing::TestTempPath("labeled_test.bin");
  LabeledStateBuffer buffer(1, 4, 2);
  for (int i = 0; i < 6; ++i) buffer.Add({double(i)}, false);
  buffer.Add({100}, true);
  buffer.Save(path);
  LabeledStateBuffer restored(1, 4, 2);
  restored.Load(path);
  EXPECT_EQ(restored.NewestSafe(4), buffer.NewestSafe(4));
  EXPECT_EQ(restored.AllUnsafe(), std::vector<float>({100}));
  std::remove(path.c_str());
}

TEST(LabeledStateBufferTest, BeforeTheRingWrapsTheLastSlotsAreTheNewest) {
  LabeledStateBuffer buffer(1, /*safe_capacity=*/4, /*unsafe_capacity=*/2);
  for (int i = 0; i < 3; ++i) buffer.Add({double(i)}, false);
  EXPECT_EQ(buffer.LastSafeSlots(2), buffer.NewestSafe(2));
  EXPECT_EQ(buffer.LastSafeSlots(2), std::vector<float>({1, 2}));
}

TEST(LabeledStateBufferTest, KeepsLabelsApartAndReturnsTheNewestSafeStates) {
  LabeledStateBuffer buffer(1, /*safe_capacity=*/4, /*unsafe_capacity=*/2);
  for (int i = 0; i < 6; ++i) buffer.Add({double(i)}, false);  // 2..5 remain
  buffer.Add({100}, true);
  buffer.Add({101}, true);
  buffer.Add({102}, true);  // 100 overwritten
  EXPECT_EQ(buffer.safe_size(), 4);
  EXPECT_EQ(buffer.unsafe_size(), 2);
  EXPECT_EQ(buffer.NewestSafe(2), std::vector<float>({4, 5}));
  EXPECT_EQ(buffer.NewestSafe(10), std::vector<float>({2, 3, 4, 5}));
  EXPECT_EQ(buffer.AllUnsafe(), std::vector<float>({101, 102}));
  // The original's x0[-2:] after the wrap: slots 2 and 3 hold 2 and 3, not the newest.
  EXPECT_EQ(buffer.LastSafeSlots(2), std::vector<float>({2, 3}));
  EXPECT_EQ(buffer.LastSafeSlots(10), std::vector<float>({4, 5, 2, 3}));
  EXPECT_THAT(ErrorMessage([&] {
                buffer.Add({1, 2}, false);
              }),
              ::testing::HasSubstr("labeled state has 2 entries, expected 1"));
}

}  // namespace
}  // namespace cmbrl

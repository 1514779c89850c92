#include "cmbrl/models/labeled_state_buffer.h"

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

#include "cmbrl/core/parallel.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <atomic>
#include <numeric>
#include <stdexcept>
#include <string>

namespace cmbrl {
namespace {

TEST(ParallelTest, RangesCoverTheLoopOnceWhateverTheWorkers) {
  for (const int workers : {1, 2, 3, 7}) {
    std::vector<std::atomic<int>> visits(100);
    ParallelRanges(100, workers, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t i = begin; i < end; ++i) ++visits[static_cast<size_t>(i)];
    });
    for (const auto& count : visits) EXPECT_EQ(count.load(), 1) << workers << " workers";
  }
}

// A part that throws on a helper thread does not end the process: every part finishes, then
// the exception reaches the caller.
TEST(ParallelTest, AnExceptionOfAnyPartReachesTheCaller) {
  for (const int failing : {0, 2}) {
    std::atomic<int> finished{0};
    try {
      ParallelRanges(4, 4, [&](std::int64_t begin, std::int64_t) {
        if (begin == failing) throw std::runtime_error("part " + std::to_string(begin));
        ++finished;
      });
      ADD_FAILURE() << "expected the exception of part " << failing;
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(error.what(), "part " + std::to_string(failing));
    }
    EXPECT_EQ(finished.load(), 3);
  }
}

// A process pinned to some CPUs (taskset, Slurm, a sweep's share) counts only those: threads
// beyond them would only wait for one another.
TEST(ParallelTest, CoreCountFollowsTheAffinityMask) {
  cpu_set_t saved;
  ASSERT_EQ(sched_getaffinity(0, sizeof(saved), &saved), 0);
  const std::vector<int> all = AllowedCpus();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(CoreCount(), static_cast<int>(all.size()));
  EXPECT_TRUE(std::is_sorted(all.begin(), all.end()));

  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(all.back(), &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  EXPECT_EQ(CoreCount(), 1);
  EXPECT_EQ(AllowedCpus(), std::vector<int>{all.back()});
  ASSERT_EQ(sched_setaffinity(0, sizeof(saved), &saved), 0);
  EXPECT_EQ(CoreCount(), static_cast<int>(all.size()));
}

}  // namespace
}  // namespace cmbrl

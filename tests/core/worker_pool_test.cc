#include "cmbrl/core/worker_pool.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

TEST(WorkerPoolTest, EveryIndexRunsOnceCallAfterCall) {
  WorkerPool pool(3);
  EXPECT_EQ(pool.threads(), 3);
  for (const std::int64_t count : {0, 1, 2, 3, 7, 1000}) {
    for (int call = 0; call < 50; ++call) {
      std::vector<int> seen(static_cast<size_t>(count), 0);
      pool.Run(count, [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) ++seen[static_cast<size_t>(i)];
      });
      for (const int times : seen) ASSERT_EQ(times, 1) << "count " << count;
    }
  }
}

TEST(WorkerPoolTest, APartsExceptionReachesTheCallerAndThePoolGoesOn) {
  WorkerPool pool(2);
  EXPECT_THROW(pool.Run(10,
                        [](std::int64_t begin, std::int64_t) {
                          if (begin > 0) throw std::runtime_error("second part");
                        }),
               std::runtime_error);
  int total = 0;
  pool.Run(4, [&](std::int64_t begin, std::int64_t end) {
    if (begin == 0) total += static_cast<int>(end - begin);
  });
  EXPECT_EQ(total, 2);
  EXPECT_THROW(WorkerPool(0), Error);
}

}  // namespace
}  // namespace cmbrl

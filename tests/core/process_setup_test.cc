#include "cmbrl/core/process_setup.h"

#include <gtest/gtest.h>

namespace cmbrl {
namespace {

TEST(ProcessSetupTest, OnlyCoresWithoutAvx2KernelsCountAsSlow) {
  EXPECT_TRUE((BlasKernelInfo{"Prescott", "SkylakeX"}.slow()));
  EXPECT_TRUE((BlasKernelInfo{"CORE2", "Haswell"}.slow()));
  EXPECT_FALSE((BlasKernelInfo{"Haswell", "SkylakeX"}.slow()));
  EXPECT_FALSE((BlasKernelInfo{"cooperlake", "Cooperlake"}.slow()));
  EXPECT_FALSE((BlasKernelInfo{"Zen", "Haswell"}.slow()));
  // No OpenBLAS in the process, or a CPU without AVX2: nothing to fix.
  EXPECT_FALSE((BlasKernelInfo{"", "SkylakeX"}.slow()));
  EXPECT_FALSE((BlasKernelInfo{"Prescott", ""}.slow()));
}

TEST(ProcessSetupTest, BestCoreFollowsTheCpusFeatures) {
  __builtin_cpu_init();
  const BlasKernelInfo info = DetectBlasKernels();
  if (__builtin_cpu_supports("avx512f")) {
    EXPECT_TRUE(info.best_core == "SkylakeX" || info.best_core == "Cooperlake") << info.best_core;
  } else if (__builtin_cpu_supports("avx2")) {
    EXPECT_EQ(info.best_core, "Haswell");
  } else {
    EXPECT_EQ(info.best_core, "");
  }
  EXPECT_EQ(info.core, "") << "this test program does not load OpenBLAS";
  EXPECT_EQ(info.threads, 0) << "this test program does not load OpenBLAS";
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/core/torch_util.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <thread>

namespace cmbrl {
namespace {

int BlasThreads() {
  using GetThreads = int (*)();
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return get != nullptr ? get() : 0;
}

TEST(ScopedSingleThreadedMathTest, OneThreadWhileAliveThenTheCountsBefore) {
  at::set_num_threads(2);
  const int blas_before = BlasThreads();
  {
    const ScopedSingleThreadedMath single;
    EXPECT_EQ(at::get_num_threads(), 1);
    if (blas_before > 0) {
      EXPECT_EQ(BlasThreads(), 1);
    }
    // Threads started meanwhile see one thread too.
    int seen = 0;
    std::thread([&] { seen = at::get_num_threads(); }).join();
    EXPECT_EQ(seen, 1);
  }
  EXPECT_EQ(at::get_num_threads(), 2);
  EXPECT_EQ(BlasThreads(), blas_before);
}

// The same product on one thread inside the guard, whatever the threads outside it.
TEST(ScopedSingleThreadedMathTest, NumbersDoNotDependOnTheThreadsOutside) {
  const torch::Tensor a = torch::rand({300, 200}, MakeCpuGenerator(1));
  const torch::Tensor b = torch::rand({200, 100}, MakeCpuGenerator(2));
  torch::Tensor results[2];
  for (const int threads : {1, 2}) {
    at::set_num_threads(threads);
    const ScopedSingleThreadedMath single;
    results[threads - 1] = torch::tanh(torch::mm(a, b)).sum(0);
  }
  EXPECT_TRUE(torch::equal(results[0], results[1]));
}

}  // namespace
}  // namespace cmbrl

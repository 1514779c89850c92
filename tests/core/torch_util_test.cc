#include "cmbrl/core/torch_util.h"

#include <dlfcn.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <thread>

#include "cmbrl/core/check.h"

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

TEST(ParseDeviceTest, TheCpuAndBadNamesNamedByKeyAndValue) {
  EXPECT_TRUE(ParseDevice("cpu", "device").is_cpu());
  try {
    ParseDevice("gpu", "training.device");
    FAIL() << "'gpu' was taken for a device";
  } catch (const Error& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("training.device 'gpu' is not a device"));
  }
}

// A bare 'cuda' is named as the tensors on it name themselves ('cuda:0'), so that the device
// checks of every model compare like with like; where no GPU is seen, it is refused by name.
TEST(ParseDeviceTest, BareCudaIsItsFirstDeviceOrRefusedWithoutOne) {
  if (!torch::cuda::is_available()) {
    try {
      ParseDevice("cuda", "device");
      FAIL() << "'cuda' was taken without a GPU";
    } catch (const Error& error) {
      EXPECT_THAT(error.what(), ::testing::HasSubstr("device 'cuda' asks for CUDA"));
    }
    return;
  }
  const torch::Device device = ParseDevice("cuda", "device");
  EXPECT_EQ(device, torch::Device(torch::kCUDA, 0));
  const torch::Tensor on_it = torch::zeros({2, 3}, torch::TensorOptions(device));
  EXPECT_NO_THROW(CheckFloatTensor(on_it, "states", 3, device));
}

}  // namespace
}  // namespace cmbrl

// Sampling of the normal truncated to the action box.
#include "cmbrl/planning/truncated_normal.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "cmbrl/core/torch_util.h"

namespace cmbrl {
namespace {

TEST(TruncatedNormalTest, StaysInTheBoxAndMatchesTheTruncatedMoments) {
  at::Generator generator = MakeCpuGenerator(0);
  const torch::Tensor mean = torch::tensor({0.0f, 0.8f, -0.5f});
  const torch::Tensor variance = torch::tensor({1.0f, 1.0f, 1e-4f});
  const torch::Tensor x = SampleTruncatedNormal(mean, variance, 200000, -1, 1, generator);
  EXPECT_GE(x.min().item<float>(), -1.0f);
  EXPECT_LE(x.max().item<float>(), 1.0f);
  const torch::Tensor m = x.mean(0);
  // N(0, 1) on [-1, 1]: mean 0, variance 1 - 2 phi(1) / (2 Phi(1) - 1) = 0.2911.
  EXPECT_NEAR(m[0].item<float>(), 0.0f, 0.005f);
  EXPECT_NEAR(x.select(1, 0).var().item<float>(), 0.2911f, 0.005f);
  // N(0.8, 1) on [-1, 1]: mean 0.8 + (phi(-1.8) - phi(0.2)) / (Phi(0.2) - Phi(-1.8)) = 0.2256.
  EXPECT_NEAR(m[1].item<float>(), 0.2256f, 0.005f);
  // A narrow normal well inside the box is untouched by the bounds.
  EXPECT_NEAR(m[2].item<float>(), -0.5f, 1e-3f);
  EXPECT_NEAR(x.select(1, 2).std().item<float>(), 0.01f, 1e-3f);
}

}  // namespace
}  // namespace cmbrl

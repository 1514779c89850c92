#include "cmbrl/planning/colored_noise.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "cmbrl/core/torch_util.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

const torch::Device kCpu(torch::kCPU);

// The covariance (H, H) of the sequences the map makes from white normals.
torch::Tensor Covariance(const ColoredNoise& noise) {
  return noise.map().matmul(noise.map().t());
}

TEST(ColoredNoiseTest, ExponentZeroIsWhiteNoiseForOddAndEvenHorizons) {
  for (const int horizon : {1, 2, 7, 8}) {
    SCOPED_TRACE(horizon);
    // Float32 rounding of an orthogonal map: 1e-5 is some 100 times its error.
    EXPECT_TRUE(torch::allclose(Covariance(ColoredNoise(horizon, 0.0, kCpu)),
                                torch::eye(horizon), 0, 1e-5));
  }
}

TEST(ColoredNoiseTest, EveryStepHasUnitVarianceAndNeighboursCorrelateMoreAsTheExponentGrows) {
  double previous_lag1 = 0;
  for (const double exponent : {1.0, 2.0, 4.0}) {
    SCOPED_TRACE(exponent);
    const torch::Tensor covariance = Covariance(ColoredNoise(8, exponent, kCpu));
    EXPECT_TRUE(torch::allclose(covariance.diagonal(), torch::ones({8}), 0, 1e-5));
    const double lag1 = covariance[0][1].item<double>();
    // The process is circular, so stationary: every neighbouring pair alike.
    EXPECT_TRUE(torch::allclose(covariance.diagonal(1), torch::full({7}, lag1), 0, 1e-5));
    EXPECT_GT(lag1, previous_lag1 + 0.1);  // measured: 0.34, 0.58, 0.76
    previous_lag1 = lag1;
  }
}

TEST(ColoredNoiseTest, SamplesHaveTheMapsMomentsAndRepeatWithTheGenerator) {
  const ColoredNoise noise(8, 2.0, kCpu);
  at::Generator generator = MakeGenerator(kCpu, 3);
  const torch::Tensor samples = noise.Sample(20000, 2, generator);  // (N, H, A)
  ASSERT_EQ(samples.sizes(), torch::IntArrayRef({20000, 8, 2}));
  const torch::Tensor flat = samples.transpose(1, 2).reshape({40000, 8}).to(torch::kDouble);
  const torch::Tensor empirical = flat.t().matmul(flat) / 40000;
  // 40000 sequences: a (co)variance's standard error is about sqrt(2 / 40000) = 0.007; 0.04 is
  // more than five of them.
  EXPECT_TRUE(torch::allclose(empirical, Covariance(noise).to(torch::kDouble), 0, 0.04));
  EXPECT_LT(flat.mean().abs().item<double>(), 0.03);
  // The action dimensions are independent.
  const torch::Tensor cross = (samples.select(2, 0) * samples.select(2, 1)).mean();
  EXPECT_LT(cross.abs().item<double>(), 0.03);

  at::Generator again = MakeGenerator(kCpu, 3);
  EXPECT_TRUE(torch::equal(noise.Sample(20000, 2, again), samples));
}

TEST(ColoredNoiseTest, BadSettingsAreRefusedByName) {
  EXPECT_NE(ErrorMessage([] { ColoredNoise(8, -1.0, kCpu); })
                .find("noise_exponent is -1: expected a number in [0, 10]"),
            std::string::npos);
  EXPECT_NE(ErrorMessage([] { ColoredNoise(8, NAN, kCpu); }).find("noise_exponent is nan"),
            std::string::npos);
  EXPECT_NE(ErrorMessage([] { ColoredNoise(0, 2.0, kCpu); }).find("horizon is 0"),
            std::string::npos);
}

}  // namespace
}  // namespace cmbrl

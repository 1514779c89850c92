#include "cmbrl/models/normalizer.h"

#include <gtest/gtest.h>

namespace cmbrl {
namespace {

TEST(NormalizerTest, ZScoresWithUnbiasedStdAndRoundTrips) {
  const torch::Tensor data = torch::tensor({{1.0f, 5.0f, 2.0f}, {3.0f, 5.0f, 2.0005f}});
  Normalizer normalizer(3);
  normalizer.Fit(data, 1e-3);
  // Column 0: mean 2, std (N - 1) sqrt(2); column 1 constant and column 2 below 1e-3: std 1.
  EXPECT_NEAR(normalizer.mean()[0].item<float>(), 2.0f, 1e-6);
  EXPECT_NEAR(normalizer.std()[0].item<float>(), std::sqrt(2.0f), 1e-6);
  EXPECT_EQ(normalizer.std()[1].item<float>(), 1.0f);
  EXPECT_EQ(normalizer.std()[2].item<float>(), 1.0f);
  const torch::Tensor z = normalizer.Normalize(data);
  EXPECT_NEAR(z[0][0].item<float>(), -1.0f / std::sqrt(2.0f), 1e-6);
  EXPECT_EQ(z[0][1].item<float>(), 0.0f);
  // float32 round trip: within a few ulps of values of order 5.
  EXPECT_TRUE(torch::allclose(normalizer.Denormalize(z), data, 0, 1e-6));
}

TEST(NormalizerTest, IdentityBeforeFitting) {
  Normalizer normalizer(2);
  const torch::Tensor x = torch::tensor({{3.0f, -4.0f}});
  EXPECT_TRUE(torch::equal(normalizer.Normalize(x), x));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/planning/truncated_normal.h"

#include <cmath>
#include <vector>

namespace cmbrl {

torch::Tensor SampleTruncatedNormal(const torch::Tensor& mean, const torch::Tensor& variance,
                                    std::int64_t count, double low, double high,
                                    at::Generator& generator) {
  const torch::Tensor std = variance.clamp_min(0).sqrt().clamp_min(1e-12);
  const auto cdf = [](const torch::Tensor& z) {
    return 0.5 * (1 + torch::erf(z / std::sqrt(2.0)));
  };
  const torch::Tensor lower = cdf((low - mean) / std);
  const torch::Tensor upper = cdf((high - mean) / std);
  std::vector<std::int64_t> shape = {count};
  shape.insert(shape.end(), mean.sizes().begin(), mean.sizes().end());
  const torch::Tensor u = torch::rand(shape, generator, mean.options());
  // Keep p strictly inside (0, 1): erfinv(+-1) is infinite.
  const torch::Tensor p = (lower + u * (upper - lower)).clamp(1e-7, 1 - 1e-7);
  const torch::Tensor x = mean + std * std::sqrt(2.0) * torch::erfinv(2 * p - 1);
  return x.clamp(low, high);
}

}  // namespace cmbrl

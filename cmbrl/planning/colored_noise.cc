#include "cmbrl/planning/colored_noise.h"

#include <cmath>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/planning/planning_options.h"

namespace cmbrl {

ColoredNoise::ColoredNoise(int horizon, double exponent, const torch::Device& device) {
  Require(horizon >= 1, "the colored noise's horizon is {}: expected 1 or more steps", horizon);
  ValidateNoiseExponent(exponent);
  const int h = horizon;
  // The amplitude of frequency k / H; the zero frequency takes the lowest one's, 1 / H.
  const auto amplitude = [&](int k) {
    return std::pow(static_cast<double>(std::max(k, 1)) / h, -exponent / 2);
  };
  // The inverse real DFT of coefficients with independent normal real and imaginary parts, as
  // columns: the mean (k = 0), a cosine and a sine for each 0 < k < H / 2, and for an even H the
  // alternating Nyquist term. Their weights give every column the same norm at exponent 0, so
  // that white noise stays white; there are H columns in all.
  std::vector<double> map(static_cast<size_t>(h) * h, 0.0);
  const auto at = [&](int t, int column) -> double& {
    return map[static_cast<size_t>(t) * h + column];
  };
  const double pi = std::acos(-1.0);
  for (int t = 0; t < h; ++t) {
    int column = 0;
    at(t, column++) = std::sqrt(2.0) * amplitude(0);
    for (int k = 1; 2 * k < h; ++k) {
      const double phase = 2 * pi * k * t / h;
      at(t, column++) = 2 * amplitude(k) * std::cos(phase);
      at(t, column++) = -2 * amplitude(k) * std::sin(phase);
    }
    if (h % 2 == 0) at(t, column++) = std::sqrt(2.0) * amplitude(h / 2) * ((t % 2) ? -1.0 : 1.0);
  }
  // Every row has the same norm (the process is circular, so stationary): unit variance.
  double row_norm = 0;
  for (int column = 0; column < h; ++column) row_norm += at(0, column) * at(0, column);
  row_norm = std::sqrt(row_norm);
  for (double& value : map) value /= row_norm;
  map_ = torch::tensor(map, torch::kDouble).view({h, h}).to(torch::kFloat).to(device);
}

torch::Tensor ColoredNoise::Sample(std::int64_t count, std::int64_t action_dim,
                                   at::Generator& generator) const {
  const std::int64_t h = map_.size(0);
  const torch::Tensor white = torch::randn({count, action_dim, h}, generator, map_.options());
  return white.matmul(map_.t()).transpose(1, 2).contiguous();  // (count, H, A)
}

}  // namespace cmbrl

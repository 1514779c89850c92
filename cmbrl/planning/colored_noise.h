// Temporally correlated Gaussian noise over a planning horizon, as iCEM samples its actions
// (Pinneri et al., "Sample-efficient Cross-Entropy Method for Real-time Planning", 2020): power
// spectral density proportional to 1 / f^exponent along the horizon, unit variance at every step.
#pragma once

#include <torch/torch.h>

#include <cstdint>

namespace cmbrl {

// Draws sequences of colored noise. The horizon's Fourier coefficients (Timmer and Koenig's
// construction, the lowest frequency 1/H standing in for 0) are a fixed linear map of white
// normals, built once: a draw is one product. Exponent 0 is white noise; larger exponents give
// smoother sequences (iCEM: 2 to 4). The map is const after construction, so one instance may
// be read by several threads; the generator given to Sample may not be shared.
class ColoredNoise {
 public:
  // Throws cmbrl::Error for a horizon below 1 or an exponent outside [0, 10].
  ColoredNoise(int horizon, double exponent, const torch::Device& device);

  // (count, H, action_dim) float32 on the device: each (., ., a) an independent sequence with
  // mean 0 and variance 1 at every step.
  torch::Tensor Sample(std::int64_t count, std::int64_t action_dim,
                       at::Generator& generator) const;

  // (H, H): sequence = map @ white normals. For tests and the curious.
  const torch::Tensor& map() const { return map_; }

 private:
  torch::Tensor map_;  // (H, H) float32 on the device
};

}  // namespace cmbrl

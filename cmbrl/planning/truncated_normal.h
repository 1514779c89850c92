// Sampling a normal distribution truncated to a box, by inverting its CDF (as the paper's code).
#pragma once

#include <torch/torch.h>

#include <cstdint>

namespace cmbrl {

// `count` samples (count, ...mean.shape) of N(mean, variance) truncated to [low, high], drawn on
// mean's device from `generator`: u ~ U(Phi(a), Phi(b)), x = mean + std * Phi^-1(u), with a, b
// the standardised bounds. Zero variance gives the mean (clamped to the box).
torch::Tensor SampleTruncatedNormal(const torch::Tensor& mean, const torch::Tensor& variance,
                                    std::int64_t count, double low, double high,
                                    at::Generator& generator);

}  // namespace cmbrl

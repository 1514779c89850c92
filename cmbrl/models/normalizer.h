// Z-score normalisation of model inputs and targets (facts B3).
#pragma once

#include <torch/torch.h>

namespace cmbrl {

// Per-column mean and standard deviation. Not thread-safe while fitting; Normalize and
// Denormalize are const and safe to call concurrently.
class Normalizer {
 public:
  // Identity (mean 0, std 1) over `dim` columns, on the CPU.
  explicit Normalizer(int dim = 0);

  // Statistics over the rows of `data` (rows, dim): std with N - 1; any std below `min_std`
  // (and the std of a single row) becomes 1, so constant columns pass through unscaled.
  void Fit(const torch::Tensor& data, double min_std);

  torch::Tensor Normalize(const torch::Tensor& x) const { return (x - mean_) / std_; }
  torch::Tensor Denormalize(const torch::Tensor& z) const { return z * std_ + mean_; }

  // Moves the statistics to a device (float32 there).
  void To(const torch::Device& device);

  const torch::Tensor& mean() const { return mean_; }  // (dim)
  const torch::Tensor& std() const { return std_; }    // (dim)
  void Set(torch::Tensor mean, torch::Tensor std);

 private:
  torch::Tensor mean_;
  torch::Tensor std_;
};

}  // namespace cmbrl

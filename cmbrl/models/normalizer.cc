#include "cmbrl/models/normalizer.h"

#include "cmbrl/core/check.h"

namespace cmbrl {

Normalizer::Normalizer(int dim) : mean_(torch::zeros({dim})), std_(torch::ones({dim})) {}

void Normalizer::Fit(const torch::Tensor& data, double min_std) {
  Require(data.dim() == 2, "normaliser data must be (rows, columns), got {} dimensions",
          data.dim());
  const auto device = mean_.device();
  const torch::Tensor rows = data.to(torch::kFloat);
  const torch::Tensor mean = rows.mean(0);
  torch::Tensor std = rows.size(0) > 1 ? rows.std(0, /*unbiased=*/true) : torch::ones_like(mean);
  std = torch::where(std < min_std, torch::ones_like(std), std);
  mean_ = mean.to(device);
  std_ = std.to(device);
}

void Normalizer::To(const torch::Device& device) {
  mean_ = mean_.to(device, torch::kFloat);
  std_ = std_.to(device, torch::kFloat);
}

void Normalizer::Set(torch::Tensor mean, torch::Tensor std) {
  Require(mean.sizes() == std.sizes() && mean.dim() == 1,
          "normaliser mean and std must be vectors of one length");
  mean_ = std::move(mean);
  std_ = std::move(std);
}

}  // namespace cmbrl

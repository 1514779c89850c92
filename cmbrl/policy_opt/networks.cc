#include "cmbrl/policy_opt/networks.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "cmbrl/core/check.h"
#include "cmbrl/policy_opt/policy_opt_options.h"

namespace cmbrl {
namespace {

// Rows per block of the hand-written passes: a block's activations stay in the core's cache.
constexpr std::int64_t kBlockRows = 1024;

}  // namespace

TanhMlp::TanhMlp(int input_dim, const std::vector<int>& hidden, int output_dim,
                 at::Generator& generator) {
  Require(input_dim >= 1 && output_dim >= 1, "MLP sizes {} -> {}: expected positive sizes",
          input_dim, output_dim);
  std::vector<int> sizes = {input_dim};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(output_dim);
  const torch::NoGradGuard no_grad;
  for (size_t l = 0; l + 1 < sizes.size(); ++l) {
    Require(sizes[l + 1] >= 1, "hidden width {} of layer {}: expected a positive width",
            sizes[l + 1], l);
    const double limit = std::sqrt(6.0 / (sizes[l] + sizes[l + 1]));
    torch::Tensor weight = torch::empty({sizes[l + 1], sizes[l]}, torch::kFloat);
    weight.uniform_(-limit, limit, generator);
    parameters_.push_back(weight.requires_grad_());
    parameters_.push_back(torch::zeros({sizes[l + 1]}, torch::kFloat).requires_grad_());
  }
}

torch::Tensor TanhMlp::Forward(const torch::Tensor& input) const {
  torch::Tensor x = input;
  const size_t layers = parameters_.size() / 2;
  for (size_t l = 0; l < layers; ++l) {
    x = torch::addmm(parameters_[2 * l + 1], x, parameters_[2 * l].t());
    if (l + 1 < layers) x = torch::tanh(x);
  }
  return x;
}

double TanhMlp::AddSquaredErrorGradient(const torch::Tensor& inputs,
                                        const torch::Tensor& targets, double scale,
                                        std::vector<torch::Tensor>& gradients) const {
  const torch::NoGradGuard no_grad;
  const size_t layers = parameters_.size() / 2;
  const std::int64_t rows = inputs.size(0);
  double squares = 0.0;
  std::vector<torch::Tensor> activations(layers + 1);
  for (std::int64_t start = 0; start < rows; start += kBlockRows) {
    const std::int64_t count = std::min(kBlockRows, rows - start);
    activations[0] = inputs.narrow(0, start, count);
    for (size_t l = 0; l < layers; ++l) {
      activations[l + 1] =
          torch::addmm(parameters_[2 * l + 1], activations[l], parameters_[2 * l].t());
      if (l + 1 < layers) activations[l + 1].tanh_();
    }
    const torch::Tensor residual =
        activations[layers].squeeze(-1) - targets.narrow(0, start, count);
    squares += residual.pow(2).sum().item<double>();
    Backward(activations, (residual * scale).unsqueeze(-1), gradients);
  }
  return squares;
}

void TanhMlp::Backward(const std::vector<torch::Tensor>& activations, torch::Tensor delta,
                       std::vector<torch::Tensor>& gradients) const {
  for (size_t l = parameters_.size() / 2; l-- > 0;) {
    gradients[2 * l].addmm_(delta.t(), activations[l]);
    gradients[2 * l + 1].add_(delta.sum(0));
    if (l > 0) {
      // Back through layer l's weights and the tanh before it: tanh' = 1 - tanh^2.
      delta = delta.mm(parameters_[2 * l]).mul_(1 - activations[l].pow(2));
    }
  }
}

TanhMlp::Jacobian::Jacobian(const TanhMlp& mlp, const torch::Tensor& inputs) : mlp_(mlp) {
  const torch::NoGradGuard no_grad;
  const size_t layers = mlp.parameters_.size() / 2;
  const std::int64_t rows = inputs.size(0);
  for (std::int64_t start = 0; start < rows; start += kBlockRows) {
    std::vector<torch::Tensor> activations = {inputs.narrow(0, start, std::min(kBlockRows, rows - start))};
    for (size_t l = 0; l + 1 < layers; ++l) {
      activations.push_back(
          torch::addmm(mlp.parameters_[2 * l + 1], activations[l], mlp.parameters_[2 * l].t())
              .tanh_());
    }
    blocks_.push_back(std::move(activations));
  }
}

void TanhMlp::Jacobian::AddGaussNewtonProduct(const std::vector<torch::Tensor>& v,
                                              const torch::Tensor& output_weights, double scale,
                                              std::vector<torch::Tensor>& product) const {
  const torch::NoGradGuard no_grad;
  const std::vector<torch::Tensor>& parameters = mlp_.parameters_;
  const size_t layers = parameters.size() / 2;
  const torch::Tensor weights = output_weights * scale;
  for (const std::vector<torch::Tensor>& activations : blocks_) {
    // The tangent pass: d(layer l's pre-activation) = x_l dW^T + db + dx_l W^T, the last term
    // absent at the input; through the tanh, times 1 - tanh^2.
    torch::Tensor tangent;
    for (size_t l = 0; l < layers; ++l) {
      torch::Tensor pre = torch::addmm(v[2 * l + 1], activations[l], v[2 * l].t());
      if (l > 0) pre.addmm_(tangent, parameters[2 * l].t());
      tangent = l + 1 < layers ? pre.mul_(1 - activations[l + 1].pow(2)) : pre;
    }
    mlp_.Backward(activations, tangent.mul_(weights), product);
  }
}

GaussianPolicy::GaussianPolicy(int observation_dim, int action_dim,
                               const std::vector<int>& hidden, double initial_log_std,
                               at::Generator& generator)
    : action_dim_(action_dim),
      mean_(observation_dim, hidden, action_dim, generator),
      log_std_(torch::full({action_dim}, initial_log_std, torch::kFloat).requires_grad_()) {}

torch::Tensor GaussianPolicy::Mean(const torch::Tensor& observations) const {
  return mean_.Forward(observations);
}

torch::Tensor GaussianPolicy::LogProb(const torch::Tensor& observations,
                                      const torch::Tensor& actions) const {
  const torch::Tensor mean = Mean(observations);
  const torch::Tensor z = (actions - mean) / (torch::exp(log_std_) + kPolicyOptEps);
  return (-0.5 * (z * z + 2 * log_std_ + std::log(2 * M_PI))).sum(-1);
}

torch::Tensor GaussianPolicy::MeanKl(const torch::Tensor& observations,
                                     const torch::Tensor& old_mean,
                                     const torch::Tensor& old_log_std) const {
  const torch::Tensor mean = Mean(observations);
  const torch::Tensor old_var = torch::exp(2 * old_log_std), var = torch::exp(2 * log_std_);
  const torch::Tensor per_dim =
      0.5 * (((mean - old_mean).pow(2) + old_var) / (var + kPolicyOptEps) - 1) + log_std_ -
      old_log_std;
  return per_dim.sum(-1).mean();
}

torch::Tensor GaussianPolicy::Sample(const torch::Tensor& observations,
                                     at::Generator& generator) const {
  const torch::NoGradGuard no_grad;
  const torch::Tensor mean = Mean(observations);
  torch::Tensor noise = torch::empty_like(mean);
  noise.normal_(0.0, 1.0, generator);
  return mean + torch::exp(log_std_) * noise;
}

double GaussianPolicy::Entropy() const {
  return (log_std_ + 0.5 * std::log(2 * M_PI * M_E)).sum().item<double>();
}

std::function<torch::Tensor(const torch::Tensor&)> GaussianPolicy::KlHessianProduct(
    const torch::Tensor& observations) const {
  // Per action dimension, KL(old || new) = ((mu - mu_old)^2 + var_old) / (2 (var + eps)) - 1/2
  // + log_std - log_std_old. Where new == old its gradient is zero, so the mean's part of the
  // Hessian is J^T diag(1 / (var + eps)) J / N; the mean and the log std do not mix; and the log
  // std's second derivative is, with u = var, 4 u^3 / (u + eps)^3 - 2 u^2 / (u + eps)^2 (2 when
  // eps = 0).
  const torch::NoGradGuard no_grad;
  const torch::Tensor var = torch::exp(2 * log_std_.to(torch::kDouble));
  const torch::Tensor mean_weights = (1 / (var + kPolicyOptEps)).to(torch::kFloat);
  const torch::Tensor log_std_curvature = (4 * var.pow(3) / (var + kPolicyOptEps).pow(3) -
                                           2 * var.pow(2) / (var + kPolicyOptEps).pow(2))
                                              .to(torch::kFloat);
  const double rows = static_cast<double>(observations.size(0));
  auto jacobian = std::make_shared<TanhMlp::Jacobian>(mean_, observations);
  return [this, jacobian, mean_weights, log_std_curvature, rows](const torch::Tensor& flat) {
    const torch::NoGradGuard no_grad;
    const std::vector<torch::Tensor>& mean_parameters = mean_.parameters();
    std::int64_t size = action_dim_;
    for (const torch::Tensor& p : mean_parameters) size += p.numel();
    Require(flat.dim() == 1 && flat.numel() == size,
            "a vector of {} values for the KL's Hessian: the policy has {} parameters",
            flat.numel(), size);
    std::vector<torch::Tensor> v, product;
    std::int64_t offset = 0;
    for (const torch::Tensor& p : mean_parameters) {
      v.push_back(flat.narrow(0, offset, p.numel()).view_as(p));
      product.push_back(torch::zeros_like(p));
      offset += p.numel();
    }
    jacobian->AddGaussNewtonProduct(v, mean_weights, 1.0 / rows, product);
    std::vector<torch::Tensor> parts;
    for (const torch::Tensor& p : product) parts.push_back(p.reshape(-1));
    parts.push_back(flat.narrow(0, offset, action_dim_) * log_std_curvature);
    return torch::cat(parts);
  };
}

std::vector<torch::Tensor> GaussianPolicy::parameters() const {
  std::vector<torch::Tensor> all = mean_.parameters();
  all.push_back(log_std_);
  return all;
}

torch::Tensor GaussianPolicy::FlatParameters() const {
  std::vector<torch::Tensor> flat;
  for (const torch::Tensor& p : parameters()) flat.push_back(p.detach().reshape(-1));
  return torch::cat(flat);
}

void GaussianPolicy::SetFlatParameters(const torch::Tensor& flat) {
  const torch::NoGradGuard no_grad;
  std::int64_t offset = 0;
  for (torch::Tensor p : parameters()) {
    const std::int64_t n = p.numel();
    Require(offset + n <= flat.numel(), "flat parameters of {} values: too few for the policy",
            flat.numel());
    p.copy_(flat.narrow(0, offset, n).view_as(p));
    offset += n;
  }
  Require(offset == flat.numel(), "flat parameters of {} values: the policy has {}", flat.numel(),
          offset);
}

torch::Tensor FlatGradient(const torch::Tensor& scalar, const std::vector<torch::Tensor>& parameters,
                           bool create_graph) {
  const std::vector<torch::Tensor> grads =
      torch::autograd::grad({scalar}, parameters, /*grad_outputs=*/{},
                            /*retain_graph=*/true, create_graph, /*allow_unused=*/true);
  std::vector<torch::Tensor> flat;
  for (size_t i = 0; i < grads.size(); ++i) {
    flat.push_back(grads[i].defined() ? grads[i].reshape(-1)
                                      : torch::zeros({parameters[i].numel()}, torch::kFloat));
  }
  return torch::cat(flat);
}

}  // namespace cmbrl

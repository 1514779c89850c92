// The networks of the model-free baselines (safety-starter-agents' defaults, paper Section V-B):
// a Gaussian policy whose mean is a tanh MLP and whose log standard deviation is one
// state-independent parameter per action, and tanh MLP value functions for rewards and costs.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cmbrl {

// A tanh MLP: Glorot-uniform weights drawn from `generator`, zero biases (TensorFlow's dense
// defaults, which the original used). Thread-compatible.
class TanhMlp {
 public:
  TanhMlp(int input_dim, const std::vector<int>& hidden, int output_dim, at::Generator& generator);
  torch::Tensor Forward(const torch::Tensor& input) const;  // (N, in) -> (N, out), no activation last
  // For a network with one output: adds to `gradients` (one tensor per parameter, shaped like
  // it) the gradient of (scale / 2) * sum over rows of (output - target)^2, and returns that sum
  // of squares. Forward and backward run over blocks of rows small enough that a block's
  // activations stay in the core's cache between them (LibTorch's autograd keeps the whole
  // batch's); the result is autograd's up to the order of the sums. No autograd graph.
  double AddSquaredErrorGradient(const torch::Tensor& inputs, const torch::Tensor& targets,
                                 double scale, std::vector<torch::Tensor>& gradients) const;
  std::vector<torch::Tensor>& parameters() { return parameters_; }
  const std::vector<torch::Tensor>& parameters() const { return parameters_; }

  // Products with J, the Jacobian of the outputs with respect to the parameters at fixed inputs:
  // Gauss-Newton products J^T diag(w) J v, the Hessian of a loss whose own Hessian in the
  // outputs is diag(w) and whose gradient there is zero. Keeps the layers' activations at the
  // inputs (about N x the hidden widths floats); valid while the network's parameters stay as
  // they were. No autograd: a tangent pass and a backward pass over blocks of rows.
  class Jacobian {
   public:
    Jacobian(const TanhMlp& mlp, const torch::Tensor& inputs);
    // Adds scale * sum over rows of J_r^T diag(output_weights) J_r v to `product`; `v` and
    // `product` hold one tensor per parameter, shaped like it; output_weights is (out).
    void AddGaussNewtonProduct(const std::vector<torch::Tensor>& v,
                               const torch::Tensor& output_weights, double scale,
                               std::vector<torch::Tensor>& product) const;

   private:
    const TanhMlp& mlp_;
    std::vector<std::vector<torch::Tensor>> blocks_;  // per block of rows, each layer's input
  };

 private:
  // Adds the gradient of sum over rows of <delta, output> to `gradients`, given each layer's
  // input (activations[0] the network's input, then the hidden layers' tanh outputs).
  void Backward(const std::vector<torch::Tensor>& activations, torch::Tensor delta,
                std::vector<torch::Tensor>& gradients) const;

  std::vector<torch::Tensor> parameters_;  // weight (out, in), bias (out), per layer
};

// pi(a | s) = N(mean(s), exp(log_std)^2), actions unclipped (the environment clips).
class GaussianPolicy {
 public:
  GaussianPolicy(int observation_dim, int action_dim, const std::vector<int>& hidden,
                 double initial_log_std, at::Generator& generator);

  int action_dim() const { return action_dim_; }
  torch::Tensor Mean(const torch::Tensor& observations) const;  // (N, A)
  const torch::Tensor& log_std() const { return log_std_; }      // (A)
  // log pi(a | s), summed over action dimensions: (N).
  torch::Tensor LogProb(const torch::Tensor& observations, const torch::Tensor& actions) const;
  // Mean KL(old || this) over the batch, the old distribution given by its (N, A) means and (A)
  // log std (the original's gaussian_kl, its 1e-8 included).
  torch::Tensor MeanKl(const torch::Tensor& observations, const torch::Tensor& old_mean,
                       const torch::Tensor& old_log_std) const;
  // (N, A) actions drawn from the policy.
  torch::Tensor Sample(const torch::Tensor& observations, at::Generator& generator) const;
  // Differential entropy, summed over action dimensions.
  double Entropy() const;
  // v -> H v for flat vectors v (FlatParameters() order, float), H the Hessian of
  // MeanKl(observations, old mean, old log std) at the current parameters, the old distribution
  // being the current one: the Fisher matrix that TRPO's and CPO's steps solve with. Exact there
  // (the mean's Gauss-Newton product with weights 1 / (var + 1e-8), the log std's diagonal) and
  // equal to autograd's double backward up to the order of the sums, at about half its work.
  // Valid while the parameters stay as they were.
  std::function<torch::Tensor(const torch::Tensor&)> KlHessianProduct(
      const torch::Tensor& observations) const;

  // Every parameter as one flat vector, in a fixed order, and back.
  std::vector<torch::Tensor> parameters() const;
  torch::Tensor FlatParameters() const;
  void SetFlatParameters(const torch::Tensor& flat);

 private:
  int action_dim_;
  TanhMlp mean_;
  torch::Tensor log_std_;
};

// Flat gradient of a scalar with respect to `parameters` (kept in the graph when `create_graph`,
// for Hessian-vector products).
torch::Tensor FlatGradient(const torch::Tensor& scalar, const std::vector<torch::Tensor>& parameters,
                           bool create_graph = false);

}  // namespace cmbrl

// The dynamics ensemble's prediction pass on the CPU through oneDNN matrix-product primitives
// (AVX-512 and AVX512-BF16 kernels picked by CPUID), the fast backend of EnsembleDynamics.
//
// One primitive per layer serves all E members (each with its own weights); bias and ReLU are
// fused into it, the output normaliser is folded into the last layer's weights, and the change
// of state (predict_delta) is added by the last product itself. Primitives and the weights in
// the layout each primitive wants are made once per batch size after every SetWeights (once per
// fit), never per call. A call is cut into (member, block of rows) tasks of fixed shape, each a
// single-threaded chain of products, spread over the process's cores: the bits depend on neither
// the number of cores nor the calling thread. oneDNN stays inside the .cc file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/models/tensor_fwd.h"

namespace cmbrl {

// Whether the backend can run here at that precision: the build has oneDNN, and for bf16 the
// CPU has AVX-512. When not, `why_not` (if given) says which is missing.
bool OnednnForwardAvailable(bool bf16, std::string* why_not = nullptr);

// The version of the oneDNN this build runs ("2.6.3"); "" without oneDNN.
std::string OnednnVersion();

// Rows of one prediction task on this CPU: 256 with AVX-512, 512 without. Part of the results
// (another block sums in another order), so one machine always predicts the same bits.
std::int64_t OnednnPredictionBlockRows();

class OnednnEnsembleForward {
 public:
  // `bf16`: weights and hidden activations in bfloat16 (float32 sums, biases and output);
  // otherwise float32 throughout. Throws cmbrl::Error when the backend is not available.
  explicit OnednnEnsembleForward(bool bf16);
  ~OnednnEnsembleForward();
  OnednnEnsembleForward(const OnednnEnsembleForward&) = delete;
  OnednnEnsembleForward& operator=(const OnednnEnsembleForward&) = delete;

  // The ensemble's float32 CPU parameters: weights[l] (E, in_l, out_l), biases[l] (E, 1, out_l),
  // and the normalisers' (mean, std) of the inputs [state, action] and of the targets. Copies
  // them; drops every cached primitive. Not safe concurrently with Predict.
  void SetWeights(const std::vector<torch::Tensor>& weights,
                  const std::vector<torch::Tensor>& biases, const torch::Tensor& input_mean,
                  const torch::Tensor& input_std, const torch::Tensor& target_mean,
                  const torch::Tensor& target_std, bool predict_delta);

  // states (E, N, S), actions (E, N, A): float32 CPU tensors, any strides -> next states
  // (E, N, S). Shapes are the caller's to check. Safe to call concurrently.
  torch::Tensor Predict(const torch::Tensor& states, const torch::Tensor& actions) const;

  bool bf16() const { return bf16_; }

 private:
  struct Impl;
  bool bf16_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmbrl

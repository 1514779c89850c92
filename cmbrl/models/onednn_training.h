// The dynamics ensemble's training products on the CPU through oneDNN fp32 matrix-product
// primitives: the forward pass, the loss and the backward pass of one minibatch step, for every
// member, written as the parameters' gradients for FusedAdam. The training half of
// EnsembleDynamics's oneDNN backend (onednn_forward.h is the prediction half).
//
// Per layer a step makes three products per member: the forward one (bias and ReLU fused), the
// weights' gradient (the layer's input transposed times the output's gradient) and, below the
// top, the input's gradient (the output's gradient times the weights transposed). The transposes
// are strides, never copies; the weights are read in their own (E, in, out) layout, since they
// change at every step. Primitives are made once per batch size and kept. Each member is one
// single-threaded task, spread over the process's cores: the bits depend on neither the number of
// cores nor the calling thread. oneDNN stays inside the .cc file.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "cmbrl/models/tensor_fwd.h"

namespace cmbrl {

class OnednnEnsembleTraining {
 public:
  // `layer_sizes`: the input width, the hidden widths, the output width. Throws cmbrl::Error
  // when the build has no oneDNN.
  explicit OnednnEnsembleTraining(std::vector<std::int64_t> layer_sizes);
  ~OnednnEnsembleTraining();
  OnednnEnsembleTraining(const OnednnEnsembleTraining&) = delete;
  OnednnEnsembleTraining& operator=(const OnednnEnsembleTraining&) = delete;

  // One minibatch of every member. `weights[l]` (E, in_l, out_l) and `biases[l]` (E, 1, out_l):
  // the float32, contiguous CPU parameters; `inputs` (n, in) and `targets` (n, out): normalised
  // float32 rows; `batch` (E, B): member m's row indices. Sets each parameter's gradient
  // (mutable_grad) of loss = sum over members of the member's mean squared error over its
  // B x out values, the loss LibTorch's path differentiates, and returns that loss. The
  // gradient tensors are this object's, set before any is computed, and are overwritten by the
  // next call. `after_member(m)`, when given, runs on the thread that made member m's gradients
  // as soon as they are complete (the optimiser's part for that member), from several threads at
  // once. Not safe to call concurrently (it keeps the primitives of each batch size it meets).
  double Gradients(std::vector<torch::Tensor>& weights, std::vector<torch::Tensor>& biases,
                   const torch::Tensor& inputs, const torch::Tensor& targets,
                   const torch::Tensor& batch,
                   const std::function<void(std::int64_t member)>& after_member = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmbrl

// The flat tree ensemble as tensors, evaluated with tensor operations on any device, so that a
// GPU planner classifies its predicted states without copying them to the host.
#pragma once

#include <torch/torch.h>

#include "cmbrl/models/tree_ensemble.h"

namespace cmbrl {

// Tensors of one FlatTreeEnsemble on one device. Immutable after construction, so thread-safe.
class TreeEnsembleTensors {
 public:
  TreeEnsembleTensors(const FlatTreeEnsemble& trees, const torch::Device& device);

  // states (M, F) float32 on this device -> margins (M) float32. All trees advance one level per
  // step for max_depth steps (gathers and selects; no host synchronisation). Rows are processed
  // in chunks to bound memory.
  torch::Tensor Margins(const torch::Tensor& states) const;

  const torch::Device& device() const { return device_; }

 private:
  torch::Device device_;
  torch::Tensor feature_;       // (nodes) int64; 0 at leaves
  torch::Tensor threshold_;     // (nodes) float32
  torch::Tensor leaf_value_;    // (nodes) float32; 0 at inner nodes
  torch::Tensor left_;          // (nodes) int64; itself at leaves
  torch::Tensor right_;         // (nodes) int64; itself at leaves
  torch::Tensor default_left_;  // (nodes) bool
  torch::Tensor roots_;         // (trees) int64
  int max_depth_ = 0;
  float base_margin_ = 0.0f;
};

}  // namespace cmbrl

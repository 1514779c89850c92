// The flat tree ensemble as tensors, evaluated with tensor operations on any device, so that a
// GPU planner classifies its predicted states without copying them to the host.
#pragma once

#include <torch/torch.h>

#include "cmbrl/models/tree_ensemble.h"

namespace cmbrl {

// Tensors of one FlatTreeEnsemble on one device. Immutable after construction, so thread-safe.
class TreeEnsembleTensors {
 public:
  // chunk_nodes bounds the (rows, trees) node indices held at once (int64, a few such tensors
  // live at a time); 0 takes the device's default: 2^21 (16 MB) on a CPU, 2^25 (256 MB) on a
  // GPU, where every chunk costs about ten kernel launches a tree level and memory is ample (the
  // paper's 128,000 states a planning step by 400 trees: 2 chunks, not 25).
  TreeEnsembleTensors(const FlatTreeEnsemble& trees, const torch::Device& device,
                      std::int64_t chunk_nodes = 0);

  // states (M, F) float32 on this device -> margins (M) float32. All trees advance one level per
  // step for max_depth steps (gathers and selects; no host synchronisation). Rows are processed
  // in chunks of chunk_rows() to bound memory; a row's margin does not depend on the chunking.
  torch::Tensor Margins(const torch::Tensor& states) const;

  const torch::Device& device() const { return device_; }
  std::int64_t chunk_rows() const { return chunk_rows_; }

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
  std::int64_t chunk_rows_ = 1;  // rows classified at once
};

}  // namespace cmbrl

// The flat tree ensemble on a device, so that a GPU planner classifies its predicted states
// without copying them to the host: on CUDA by cmbrl's own kernel where it is built (one launch
// for all trees, margins equal to the host's bit for bit), elsewhere by tensor operations.
#pragma once

#include <torch/torch.h>

#include "cmbrl/models/tree_ensemble.h"

namespace cmbrl {

// How a device evaluates the trees.
enum class DeviceTreePath {
  kFastest,    // the CUDA kernel on a CUDA device where it is built, else kTensorOps
  kTensorOps,  // every tree one level a step, as LibTorch operations (any device)
};

// Tensors of one FlatTreeEnsemble on one device. Immutable after construction, so thread-safe.
class TreeEnsembleTensors {
 public:
  // chunk_nodes (kTensorOps) bounds the (rows, trees) node indices held at once (int64, a few
  // such tensors live at a time); 0 takes the device's default: 2^21 (16 MB) on a CPU, 2^25
  // (256 MB) on a GPU, where every chunk costs six kernel launches a tree level and memory
  // is ample (the paper's 128,000 states a planning step by 400 trees: 2 chunks, not 25).
  TreeEnsembleTensors(const FlatTreeEnsemble& trees, const torch::Device& device,
                      std::int64_t chunk_nodes = 0, DeviceTreePath path = DeviceTreePath::kFastest);

  // states (M, F) float32 on this device, F covering every feature a tree tests -> margins (M)
  // float32, with no host synchronisation.
  // - The CUDA kernel: one thread a row walks every tree (RowMargin); each margin equals
  //   FlatTreeEnsemble::Margin's bit for bit.
  // - Tensor operations: all trees advance one level per step for max_depth steps, six
  //   operations a level (gathers and a comparison); rows are processed in chunks of
  //   chunk_rows() to bound memory, and a row's margin does not depend on the chunking. The
  //   leaves are summed in another order than the host's.
  torch::Tensor Margins(const torch::Tensor& states) const;

  const torch::Device& device() const { return device_; }
  std::int64_t chunk_rows() const { return chunk_rows_; }
  // Whether Margins() runs the CUDA kernel, and whether this build has it at all.
  bool uses_cuda_kernel() const { return uses_cuda_kernel_; }
  static bool CudaKernelBuilt();

 private:
  void BuildKernelTables(const FlatTreeEnsemble& trees);
  void BuildTensorOpTables(const FlatTreeEnsemble& trees, std::int64_t chunk_nodes);
  torch::Tensor KernelMargins(const torch::Tensor& states) const;
  torch::Tensor TensorOpMargins(const torch::Tensor& states) const;

  torch::Device device_;
  bool uses_cuda_kernel_ = false;
  // The kernel's: FlatTreeEnsemble's TreeNode bytes as (nodes x 4) int32, and its roots.
  torch::Tensor kernel_nodes_;
  torch::Tensor kernel_roots_;  // (trees) int32
  // The tensor operations', nodes renumbered breadth-first (a right child follows its left):
  torch::Tensor column_;       // (nodes) int64: the widened row's column a node tests; 0 at leaves
  torch::Tensor threshold_;    // (nodes) float32; NaN at leaves
  torch::Tensor first_child_;  // (nodes) int64: the left child; itself at leaves
  torch::Tensor leaf_value_;   // (nodes) float32; 0 at inner nodes
  torch::Tensor roots_;        // (trees) int64, in the path's own numbering
  std::int64_t tree_count_ = 0;
  int max_depth_ = 0;
  std::int64_t columns_needed_ = 0;  // 1 + the largest feature a node tests
  float base_margin_ = 0.0f;
  std::int64_t chunk_rows_ = 1;  // rows classified at once
};

}  // namespace cmbrl

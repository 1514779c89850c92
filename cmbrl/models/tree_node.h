// One node of a tree ensemble in the one layout every path reads (FlatTreeEnsemble on the CPU,
// the tensor tables, the CUDA kernel): 16 bytes, one vector load on a GPU; and the walk of one
// row down every tree, compiled for the host and for CUDA (tree_kernel_cuda.cu), so the kernel's
// arithmetic is the code the CPU tests run.
#pragma once

#include <cstdint>

#if defined(__CUDACC__)
#define CMBRL_HOST_DEVICE __host__ __device__
#else
#define CMBRL_HOST_DEVICE
#endif

namespace cmbrl {

// Inner nodes send x[feature] < value to `left`, anything else to `right`, and NaN the default
// way; leaves carry their value and point at themselves.
struct alignas(16) TreeNode {
  std::int32_t test = -1;  // inner: feature * 2 + 1 when NaN goes left, + 0 when right; leaf: -1
  float value = 0.0f;      // split threshold (inner) or leaf value (leaf)
  std::int32_t left = 0;   // absolute node index; a leaf's own
  std::int32_t right = 0;  // absolute node index; a leaf's own

  // feature: 0 to 2^30 - 1 (the caller checks).
  static TreeNode Split(std::int32_t split_feature, bool nan_left, float threshold,
                        std::int32_t left_child, std::int32_t right_child) {
    return {split_feature * 2 + (nan_left ? 1 : 0), threshold, left_child, right_child};
  }
  static TreeNode Leaf(std::int32_t index, float leaf_value) {
    return {-1, leaf_value, index, index};
  }

  CMBRL_HOST_DEVICE bool is_leaf() const { return test < 0; }
  CMBRL_HOST_DEVICE std::int32_t feature() const { return test >> 1; }  // inner nodes
  CMBRL_HOST_DEVICE bool default_left() const { return (test & 1) != 0; }
};
static_assert(sizeof(TreeNode) == 16, "one 16-byte load a node");

// A row's margin: base_margin plus one leaf per tree, summed in float in tree order as XGBoost
// does (NaN takes the node's default direction), so the margin is XGBoost's bit for bit.
CMBRL_HOST_DEVICE inline float RowMargin(const TreeNode* nodes, const std::int32_t* roots,
                                         int trees, float base_margin, const float* row) {
  float sum = base_margin;
  for (int t = 0; t < trees; ++t) {
    TreeNode node = nodes[roots[t]];
    while (!node.is_leaf()) {
      const float x = row[node.feature()];
      const bool missing = x != x;  // NaN
      const bool go_left = missing ? node.default_left() : x < node.value;
      node = nodes[go_left ? node.left : node.right];
    }
    sum += node.value;
  }
  return sum;
}

}  // namespace cmbrl

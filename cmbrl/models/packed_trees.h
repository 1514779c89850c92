// The tree ensemble packed for a GPU thread: 16 bytes a node, one vector load each, and the walk
// of one row down every tree, compiled both for the host (tests) and for CUDA
// (tree_kernel_cuda.cu), so the kernel's arithmetic is the code the CPU tests run.
#pragma once

#include <cstdint>
#include <vector>

#include "cmbrl/models/tree_ensemble.h"

#if defined(__CUDACC__)
#define CMBRL_HOST_DEVICE __host__ __device__
#else
#define CMBRL_HOST_DEVICE
#endif

namespace cmbrl {

struct alignas(16) PackedNode {
  std::int32_t test = -1;  // feature * 2 + default_left at inner nodes; -1 at leaves
  float value = 0.0f;      // split threshold (inner) or leaf value (leaf)
  std::int32_t left = 0;   // absolute node index; the node's own at leaves
  std::int32_t right = 0;
};
static_assert(sizeof(PackedNode) == 16, "one 16-byte load a node");

// The nodes in FlatTreeEnsemble's order (its roots index them unchanged).
std::vector<PackedNode> PackNodes(const FlatTreeEnsemble& trees);

// A row's margin: base_margin plus one leaf per tree, summed in float in tree order, as
// FlatTreeEnsemble::Margin and XGBoost do (NaN takes the node's default direction), so the
// margin is theirs bit for bit.
CMBRL_HOST_DEVICE inline float PackedRowMargin(const PackedNode* nodes, const std::int32_t* roots,
                                               int trees, float base_margin, const float* row) {
  float sum = base_margin;
  for (int t = 0; t < trees; ++t) {
    PackedNode node = nodes[roots[t]];
    while (node.test >= 0) {
      const float x = row[node.test >> 1];
      const bool missing = x != x;  // NaN
      const bool go_left = missing ? (node.test & 1) != 0 : x < node.value;
      node = nodes[go_left ? node.left : node.right];
    }
    sum += node.value;
  }
  return sum;
}

}  // namespace cmbrl

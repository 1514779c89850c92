#include "cmbrl/models/packed_trees.h"

namespace cmbrl {

std::vector<PackedNode> PackNodes(const FlatTreeEnsemble& trees) {
  const std::vector<TreeNode>& nodes = trees.nodes();
  std::vector<PackedNode> packed(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const TreeNode& node = nodes[i];
    PackedNode& out = packed[i];
    out.value = node.value;
    if (node.feature < 0) {
      out.test = -1;
      out.left = out.right = static_cast<std::int32_t>(i);
    } else {
      out.test = node.feature * 2 + (node.default_left ? 1 : 0);
      out.left = node.left;
      out.right = node.right;
    }
  }
  return packed;
}

}  // namespace cmbrl

#include "cmbrl/models/tree_ensemble_tensor.h"

#include <algorithm>
#include <vector>

#include "cmbrl/core/check.h"

namespace cmbrl {

TreeEnsembleTensors::TreeEnsembleTensors(const FlatTreeEnsemble& trees, const torch::Device& device,
                                         std::int64_t chunk_nodes)
    : device_(device), max_depth_(trees.max_depth()), base_margin_(trees.base_margin()) {
  Require(chunk_nodes >= 0,
          "tree tensors: chunk_nodes is {}: expected 0 (the device's default) "
          "or a positive count",
          chunk_nodes);
  if (chunk_nodes == 0)
    chunk_nodes = device.is_cpu() ? std::int64_t{1} << 21 : std::int64_t{1} << 25;
  const auto tree_count = static_cast<std::int64_t>(trees.roots().size());
  chunk_rows_ = std::max<std::int64_t>(1, chunk_nodes / std::max<std::int64_t>(1, tree_count));
  const std::vector<TreeNode>& nodes = trees.nodes();
  const std::int64_t n = static_cast<std::int64_t>(nodes.size());
  std::vector<std::int64_t> feature(n), left(n), right(n);
  std::vector<float> threshold(n), leaf_value(n);
  std::vector<std::uint8_t> default_left(n);
  for (std::int64_t i = 0; i < n; ++i) {
    const TreeNode& node = nodes[i];
    const bool leaf = node.feature < 0;
    feature[i] = leaf ? 0 : node.feature;
    threshold[i] = leaf ? 0.0f : node.value;
    leaf_value[i] = leaf ? node.value : 0.0f;
    left[i] = leaf ? i : node.left;
    right[i] = leaf ? i : node.right;
    default_left[i] = node.default_left;
  }
  const auto to_device = [&device](const torch::Tensor& t) { return t.to(device); };
  const auto longs = torch::TensorOptions(torch::kLong);
  feature_ = to_device(torch::tensor(feature, longs));
  left_ = to_device(torch::tensor(left, longs));
  right_ = to_device(torch::tensor(right, longs));
  threshold_ = to_device(torch::tensor(threshold, torch::kFloat));
  leaf_value_ = to_device(torch::tensor(leaf_value, torch::kFloat));
  default_left_ = to_device(torch::tensor(default_left, torch::kUInt8).to(torch::kBool));
  std::vector<std::int64_t> roots(trees.roots().begin(), trees.roots().end());
  roots_ = to_device(torch::tensor(roots, longs));
}

torch::Tensor TreeEnsembleTensors::Margins(const torch::Tensor& states) const {
  const torch::NoGradGuard no_grad;
  const std::int64_t rows = states.size(0);
  const std::int64_t trees = roots_.size(0);
  torch::Tensor margins = torch::empty({rows}, states.options());
  if (trees == 0) return margins.fill_(base_margin_);
  const std::int64_t chunk = chunk_rows_;
  for (std::int64_t begin = 0; begin < rows; begin += chunk) {
    const torch::Tensor x = states.slice(0, begin, std::min(rows, begin + chunk));  // (C, F)
    torch::Tensor node = roots_.unsqueeze(0).expand({x.size(0), trees}).contiguous();
    for (int level = 0; level < max_depth_; ++level) {
      const torch::Tensor value = x.gather(1, feature_.index({node}));  // (C, T)
      const torch::Tensor go_left = torch::where(torch::isnan(value), default_left_.index({node}),
                                                 value < threshold_.index({node}));
      node = torch::where(go_left, left_.index({node}), right_.index({node}));
    }
    // The tensor sum adds the leaves in another order than XGBoost's loop, which can move the
    // last bits of a margin; tree_ensemble_test bounds the difference.
    margins.slice(0, begin, begin + x.size(0)) = leaf_value_.index({node}).sum(1) + base_margin_;
  }
  return margins;
}

}  // namespace cmbrl

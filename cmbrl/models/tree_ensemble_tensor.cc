#include "cmbrl/models/tree_ensemble_tensor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "cmbrl/core/check.h"

#if defined(CMBRL_HAVE_CUDA_KERNELS)
#include <c10/cuda/CUDAGuard.h>
#include <c10/cuda/CUDAStream.h>

#include "cmbrl/models/tree_kernel_cuda.h"
#endif

namespace cmbrl {

bool TreeEnsembleTensors::CudaKernelBuilt() {
#if defined(CMBRL_HAVE_CUDA_KERNELS)
  return true;
#else
  return false;
#endif
}

TreeEnsembleTensors::TreeEnsembleTensors(const FlatTreeEnsemble& trees, const torch::Device& device,
                                         std::int64_t chunk_nodes, DeviceTreePath path)
    : device_(device), max_depth_(trees.max_depth()), base_margin_(trees.base_margin()) {
  Require(chunk_nodes >= 0,
          "tree tensors: chunk_nodes is {}: expected 0 (the device's default) "
          "or a positive count",
          chunk_nodes);
  for (const TreeNode& node : trees.nodes()) {
    if (!node.is_leaf())
      columns_needed_ = std::max<std::int64_t>(columns_needed_, node.feature() + 1);
  }
  tree_count_ = trees.num_trees();
  uses_cuda_kernel_ = path == DeviceTreePath::kFastest && device.is_cuda() && CudaKernelBuilt();
  if (uses_cuda_kernel_) {
    BuildKernelTables(trees);
  } else {
    BuildTensorOpTables(trees, chunk_nodes);
  }
}

void TreeEnsembleTensors::BuildKernelTables(const FlatTreeEnsemble& trees) {
  const std::vector<TreeNode>& nodes = trees.nodes();
  // Bytes, not values: a node's float travels as its int32 bits.
  std::vector<std::int32_t> words(nodes.size() * 4);
  if (!nodes.empty()) std::memcpy(words.data(), nodes.data(), words.size() * 4);
  kernel_nodes_ = torch::tensor(words, torch::kInt).to(device_);
  kernel_roots_ = torch::tensor(trees.roots(), torch::kInt).to(device_);
}

void TreeEnsembleTensors::BuildTensorOpTables(const FlatTreeEnsemble& trees,
                                              std::int64_t chunk_nodes) {
  if (chunk_nodes == 0)
    chunk_nodes = device_.is_cpu() ? std::int64_t{1} << 21 : std::int64_t{1} << 25;
  chunk_rows_ = std::max<std::int64_t>(1, chunk_nodes / std::max<std::int64_t>(1, tree_count_));
  const std::vector<TreeNode>& nodes = trees.nodes();
  const auto longs = torch::TensorOptions(torch::kLong);
  std::vector<std::int64_t> roots(trees.roots().begin(), trees.roots().end());
  // Breadth-first renumbering, tree by tree, so that a right child directly follows its left
  // sibling: the next node is then first_child + (goes right), one addition.
  std::vector<std::int32_t> order;  // new index -> FlatTreeEnsemble's
  std::vector<std::int64_t> renumbered(nodes.size(), -1);
  order.reserve(nodes.size());
  for (std::int64_t& root : roots) {
    const size_t begin = order.size();
    renumbered[root] = static_cast<std::int64_t>(order.size());
    order.push_back(static_cast<std::int32_t>(root));
    root = renumbered[root];
    for (size_t k = begin; k < order.size(); ++k) {
      const TreeNode& node = nodes[order[k]];
      if (node.is_leaf()) continue;
      for (const std::int32_t child : {node.left, node.right}) {
        renumbered[child] = static_cast<std::int64_t>(order.size());
        order.push_back(child);
      }
    }
  }
  const std::int64_t count = static_cast<std::int64_t>(order.size());
  std::vector<std::int64_t> column(count), first_child(count);
  std::vector<float> threshold(count), leaf_value(count);
  for (std::int64_t k = 0; k < count; ++k) {
    const TreeNode& node = nodes[order[k]];
    if (node.is_leaf()) {
      // A leaf stays a leaf: x >= NaN is false, so the walk adds 0 to its own index.
      column[k] = 0;
      threshold[k] = std::numeric_limits<float>::quiet_NaN();
      first_child[k] = k;
      leaf_value[k] = node.value;
      continue;
    }
    Require(std::isfinite(node.value),
            "tree tensors: node {} splits at {}: expected a finite threshold", order[k],
            node.value);
    // The row's value with NaN as -inf where NaN goes left, as +inf where it goes right (the
    // second half of the widened row): one comparison then sends NaN the default way.
    column[k] = node.feature() + (node.default_left() ? 0 : columns_needed_);
    threshold[k] = node.value;
    first_child[k] = renumbered[node.left];
    leaf_value[k] = 0.0f;
  }
  const auto to_device = [this](const torch::Tensor& t) { return t.to(device_); };
  roots_ = to_device(torch::tensor(roots, longs));
  column_ = to_device(torch::tensor(column, longs));
  first_child_ = to_device(torch::tensor(first_child, longs));
  threshold_ = to_device(torch::tensor(threshold, torch::kFloat));
  leaf_value_ = to_device(torch::tensor(leaf_value, torch::kFloat));
}

torch::Tensor TreeEnsembleTensors::Margins(const torch::Tensor& states) const {
  const bool on_device = states.defined() && states.device().type() == device_.type() &&
                         (!device_.has_index() || states.device().index() == device_.index());
  Require(on_device && states.scalar_type() == torch::kFloat,
          "tree tensors: states must be float32 on {}", device_.str());
  Require(states.dim() == 2 && states.size(1) >= columns_needed_,
          "tree tensors: states of shape {}: expected (rows, columns) with at least {} columns, "
          "the trees' largest feature index plus one",
          c10::str(states.sizes()), columns_needed_);
  const torch::NoGradGuard no_grad;
  if (tree_count_ == 0) {
    return torch::full({states.size(0)}, base_margin_, states.options());
  }
  return uses_cuda_kernel_ ? KernelMargins(states) : TensorOpMargins(states);
}

torch::Tensor TreeEnsembleTensors::KernelMargins(const torch::Tensor& states) const {
#if defined(CMBRL_HAVE_CUDA_KERNELS)
  c10::cuda::OptionalCUDAGuard guard;
  if (device_.has_index()) guard.set_device(device_);
  const torch::Tensor rows = states.contiguous();
  torch::Tensor margins = torch::empty({rows.size(0)}, rows.options());
  const char* error = cuda_trees::LaunchMargins(
      reinterpret_cast<const TreeNode*>(kernel_nodes_.data_ptr<std::int32_t>()),
      kernel_roots_.data_ptr<std::int32_t>(), static_cast<int>(kernel_roots_.size(0)), base_margin_,
      rows.data_ptr<float>(), rows.size(0), static_cast<int>(rows.size(1)),
      margins.data_ptr<float>(), c10::cuda::getCurrentCUDAStream().stream());
  Require(error == nullptr, "the trees' CUDA kernel failed to launch on {}: {}", device_.str(),
          error == nullptr ? "" : error);
  return margins;
#else
  (void)states;
  Fail("the trees' CUDA kernel is not in this build");
#endif
}

torch::Tensor TreeEnsembleTensors::TensorOpMargins(const torch::Tensor& states) const {
  const std::int64_t rows = states.size(0);
  const std::int64_t trees = tree_count_;
  const float infinity = std::numeric_limits<float>::infinity();
  torch::Tensor margins = torch::empty({rows}, states.options());
  const std::int64_t chunk = chunk_rows_;
  for (std::int64_t begin = 0; begin < rows; begin += chunk) {
    // (C, 2 W): the tested columns with NaN as -inf, then with NaN as +inf (see column_).
    const torch::Tensor x =
        states.slice(0, begin, std::min(rows, begin + chunk)).narrow(1, 0, columns_needed_);
    const torch::Tensor missing = torch::isnan(x);
    const torch::Tensor widened =
        torch::cat({x.masked_fill(missing, -infinity), x.masked_fill(missing, infinity)}, 1);
    torch::Tensor node = roots_.unsqueeze(0).expand({x.size(0), trees}).contiguous();
    // Six operations a level, each over (C, T): the column, the value, the threshold, the
    // comparison, the first child, the step.
    for (int level = 0; level < max_depth_; ++level) {
      const torch::Tensor value = widened.gather(1, column_.take(node));
      node = first_child_.take(node) + (value >= threshold_.take(node));
    }
    // The tensor sum adds the leaves in another order than XGBoost's loop, which can move the
    // last bits of a margin; tree_ensemble_test bounds the difference.
    margins.slice(0, begin, begin + x.size(0)) = leaf_value_.take(node).sum(1) + base_margin_;
  }
  return margins;
}

}  // namespace cmbrl

#include "cmbrl/models/tree_ensemble_tensor.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/models/packed_trees.h"

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
  const std::vector<TreeNode>& nodes = trees.nodes();
  const std::int64_t n = static_cast<std::int64_t>(nodes.size());
  for (const TreeNode& node : nodes) {
    columns_needed_ = std::max<std::int64_t>(columns_needed_, node.feature + 1);
  }
  const auto longs = torch::TensorOptions(torch::kLong);
  std::vector<std::int64_t> roots(trees.roots().begin(), trees.roots().end());
  roots_ = torch::tensor(roots, longs).to(device);
  uses_cuda_kernel_ = path == DeviceTreePath::kFastest && device.is_cuda() && CudaKernelBuilt();
  if (uses_cuda_kernel_) {
    const std::vector<PackedNode> packed = PackNodes(trees);
    // Bytes, not values: a node's float travels as its int32 bits.
    std::vector<std::int32_t> words(packed.size() * 4);
    if (!packed.empty()) std::memcpy(words.data(), packed.data(), words.size() * 4);
    packed_nodes_ = torch::tensor(words, torch::kInt).to(device);
    roots32_ = roots_.to(torch::kInt);
    return;
  }

  if (chunk_nodes == 0)
    chunk_nodes = device.is_cpu() ? std::int64_t{1} << 21 : std::int64_t{1} << 25;
  const auto tree_count = static_cast<std::int64_t>(trees.roots().size());
  chunk_rows_ = std::max<std::int64_t>(1, chunk_nodes / std::max<std::int64_t>(1, tree_count));
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
  feature_ = to_device(torch::tensor(feature, longs));
  left_ = to_device(torch::tensor(left, longs));
  right_ = to_device(torch::tensor(right, longs));
  threshold_ = to_device(torch::tensor(threshold, torch::kFloat));
  leaf_value_ = to_device(torch::tensor(leaf_value, torch::kFloat));
  default_left_ = to_device(torch::tensor(default_left, torch::kUInt8).to(torch::kBool));
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
  if (roots_.size(0) == 0) {
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
      reinterpret_cast<const PackedNode*>(packed_nodes_.data_ptr<std::int32_t>()),
      roots32_.data_ptr<std::int32_t>(), static_cast<int>(roots32_.size(0)), base_margin_,
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
  const std::int64_t trees = roots_.size(0);
  torch::Tensor margins = torch::empty({rows}, states.options());
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

#include <cuda_runtime.h>

#include "cmbrl/models/tree_kernel_cuda.h"

namespace cmbrl::cuda_trees {
namespace {

constexpr int kThreadsPerBlock = 128;

// One thread a row. The node table (about 150 KB at the paper's 400 trees of 12 leaves) stays
// in the caches; a row's features are read where its nodes test them.
__global__ void MarginsKernel(const TreeNode* __restrict__ nodes,
                              const std::int32_t* __restrict__ roots, int trees, float base_margin,
                              const float* __restrict__ rows, std::int64_t count, int features,
                              float* __restrict__ margins) {
  const std::int64_t r = static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (r >= count) return;
  margins[r] = RowMargin(nodes, roots, trees, base_margin, rows + r * features);
}

}  // namespace

const char* LaunchMargins(const TreeNode* nodes, const std::int32_t* roots, int trees,
                          float base_margin, const float* rows, std::int64_t count, int features,
                          float* margins, void* stream) {
  if (count <= 0) return nullptr;
  const std::int64_t blocks = (count + kThreadsPerBlock - 1) / kThreadsPerBlock;
  MarginsKernel<<<static_cast<unsigned>(blocks), kThreadsPerBlock, 0,
                  static_cast<cudaStream_t>(stream)>>>(nodes, roots, trees, base_margin, rows,
                                                       count, features, margins);
  const cudaError_t status = cudaGetLastError();
  return status == cudaSuccess ? nullptr : cudaGetErrorString(status);
}

}  // namespace cmbrl::cuda_trees

// cmbrl's own CUDA kernel for the tree ensemble's margins: one thread walks one row down every
// tree (RowMargin), so a batch of margins costs one launch and no tensor between levels.
// Built only where LibTorch has CUDA and a CUDA compiler is found
// (cmake/CmbrlDependencies.cmake); TreeEnsembleTensors is its only caller. No LibTorch here.
#pragma once

#include <cstdint>

#include "cmbrl/models/tree_node.h"

namespace cmbrl::cuda_trees {

// margins[r] = RowMargin of row r, for count rows. Every pointer is device memory: nodes
// (FlatTreeEnsemble::nodes()), roots (trees), rows (count x features, row-major; the caller checks
// that every tested feature is a column). Launched on `stream` (a cudaStream_t). Returns nullptr,
// or CUDA's message when the launch failed.
const char* LaunchMargins(const TreeNode* nodes, const std::int32_t* roots, int trees,
                          float base_margin, const float* rows, std::int64_t count, int features,
                          float* margins, void* stream);

}  // namespace cmbrl::cuda_trees

// A trained gradient-boosted tree ensemble as compact flat arrays, for fast batched prediction
// without XGBoost's general-purpose API (paper Section IV-A; the planner classifies tens of
// thousands of predicted states per step).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/models/tree_node.h"

namespace cmbrl {

// How Margins() evaluates the trees. Every kernel gives the same bits.
enum class TreeKernel {
  kFastest,     // bitvectors on AVX-512 where the CPU has it, else kAvx2
  kAvx2,        // bitvectors on AVX2 where the CPU has it, else kBitvectors
  kBitvectors,  // bitvectors in portable code
  kRowByRow,    // Margin() per row: the reference
};

// Binary-logistic tree ensemble: margin = base_margin + sum of one leaf per tree, summed in
// float in tree order as XGBoost does, so margins equal XGBoost's bit for bit. Immutable after
// construction, so thread-safe.
class FlatTreeEnsemble {
 public:
  FlatTreeEnsemble() = default;

  // Parses a model saved by XGBoost 1.x as JSON (XGBoosterSaveModelToBuffer with format json);
  // throws cmbrl::Error when it is not a binary:logistic gbtree model.
  static FlatTreeEnsemble FromXgboostJson(const std::string& json);

  // Margin (log-odds) of one row of num_features() floats: RowMargin, the reference walk.
  float Margin(const float* row) const;

  // Margins of `rows` rows (row-major), written to `out`, on up to `threads` threads (0: one
  // per core). Each row's sum keeps tree order, so every path and thread count gives the same
  // bits as Margin(). Trees of at most 32 leaves (the paper's have 12) take the bitvector path
  // described in the .cc file, which has no data-dependent branch and runs 16 rows per vector.
  void Margins(const float* rows, std::int64_t count, float* out, int threads = 1,
               TreeKernel kernel = TreeKernel::kFastest) const;

  int num_trees() const { return static_cast<int>(roots_.size()); }
  int num_features() const { return num_features_; }
  int max_depth() const { return max_depth_; }  // edges from a root to its deepest leaf
  float base_margin() const { return base_margin_; }
  const std::vector<TreeNode>& nodes() const { return nodes_; }
  const std::vector<std::int32_t>& roots() const { return roots_; }

 private:
  // The bitvector form of the trees (QuickScorer, Lucchese et al., SIGIR 2015): leaves are
  // numbered left to right per tree; an inner node whose test sends a row right rules out the
  // leaves of its left subtree, so its bitvector has 0 there. A row's exit leaf is the lowest
  // bit left after AND-ing the bitvectors of every node that sends it right.
  struct BitvectorTrees {
    bool usable = false;                     // every tree has at most 32 leaves
    std::vector<std::int32_t> feature;       // per inner node, trees one after another
    std::vector<float> threshold;            // per inner node
    std::vector<std::uint32_t> bitvector;    // per inner node
    std::vector<std::uint8_t> default_left;  // per inner node: NaN goes left
    std::vector<std::int32_t> node_begin;    // per tree, plus the end
    std::vector<std::int32_t> leaf_begin;    // per tree
    std::vector<float> leaf_value;           // per leaf, left to right within a tree
  };

  void BuildBitvectorTrees();
  // Up to 16 rows; columns: scratch of num_features() x 16 floats.
  enum class BlockIsa { kPortable, kAvx2, kAvx512 };
  void MarginsOfBlock(const float* rows, int count, float* columns, BlockIsa isa, float* out) const;

  std::vector<TreeNode> nodes_;
  BitvectorTrees bitvector_trees_;
  std::vector<std::int32_t> roots_;
  int num_features_ = 0;
  int max_depth_ = 0;
  float base_margin_ = 0.0f;
};

}  // namespace cmbrl

#include "cmbrl/models/tree_ensemble.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <utility>

#include "cmbrl/core/check.h"
#include "cmbrl/core/cpu_features.h"
#include "cmbrl/core/parallel.h"

namespace cmbrl {
namespace {

using Json = nlohmann::json;

const Json& Field(const Json& object, const char* key, const char* where) {
  Require(object.is_object() && object.contains(key),
          "XGBoost model JSON has no '{}' in {}: expected a model saved by XGBoost 1.x", key,
          where);
  return object.at(key);
}

// Depth of tree `tree`, whose nodes are nodes[root, root + count) (a lone leaf has depth 0). Its
// children must form a tree: a node reached twice from the root (a cycle, or a node with two
// parents) is refused by name, so later walks and recursions end. Nodes not reached from the root
// (XGBoost's pruned nodes) are allowed. An explicit stack: a deep tree cannot overflow the stack.
int CheckedDepth(const std::vector<TreeNode>& nodes, std::int32_t root, size_t count, size_t tree) {
  std::vector<char> reached(count, 0);
  std::vector<std::pair<std::int32_t, int>> pending = {{root, 0}};
  int depth = 0;
  while (!pending.empty()) {
    const auto [index, level] = pending.back();
    pending.pop_back();
    char& seen = reached[static_cast<size_t>(index - root)];
    Require(!seen, "XGBoost tree {} reaches its node {} twice: expected a tree", tree,
            index - root);
    seen = 1;
    depth = std::max(depth, level);
    const TreeNode& node = nodes[static_cast<size_t>(index)];
    if (node.is_leaf()) continue;
    pending.emplace_back(node.left, level + 1);
    pending.emplace_back(node.right, level + 1);
  }
  return depth;
}

}  // namespace

FlatTreeEnsemble FlatTreeEnsemble::FromXgboostJson(const std::string& text) {
  Json model;
  try {
    model = Json::parse(text);
  } catch (const Json::exception& error) {
    Fail("XGBoost model is not valid JSON: {}", error.what());
  }
  const Json& learner = Field(model, "learner", "the model");
  const std::string objective = Field(Field(learner, "objective", "learner"), "name", "objective");
  Require(objective == "binary:logistic", "XGBoost objective is '{}': expected binary:logistic",
          objective);
  const Json& params = Field(learner, "learner_model_param", "learner");
  FlatTreeEnsemble ensemble;
  ensemble.num_features_ =
      std::stoi(Field(params, "num_feature", "learner_model_param").get<std::string>());
  const float base_score =
      std::stof(Field(params, "base_score", "learner_model_param").get<std::string>());
  Require(base_score > 0.0f && base_score < 1.0f, "XGBoost base_score {} is outside (0, 1)",
          base_score);
  // XGBoost's ProbToMargin for the logistic objective, in float as XGBoost computes it.
  ensemble.base_margin_ = -std::log(1.0f / base_score - 1.0f);

  const Json& booster = Field(learner, "gradient_booster", "learner");
  const std::string name = Field(booster, "name", "gradient_booster");
  Require(name == "gbtree", "XGBoost booster is '{}': expected gbtree", name);
  for (const Json& tree : Field(Field(booster, "model", "gradient_booster"), "trees", "model")) {
    const auto& left = Field(tree, "left_children", "tree");
    const auto& right = Field(tree, "right_children", "tree");
    const auto& feature = Field(tree, "split_indices", "tree");
    const auto& value = Field(tree, "split_conditions", "tree");
    const auto& default_left = Field(tree, "default_left", "tree");
    const std::int32_t offset = static_cast<std::int32_t>(ensemble.nodes_.size());
    const size_t count = left.size();
    Require(right.size() == count && feature.size() == count && value.size() == count &&
                default_left.size() == count,
            "XGBoost tree arrays differ in length");
    Require(count > 0, "XGBoost tree {} has no nodes", ensemble.roots_.size());
    for (size_t i = 0; i < count; ++i) {
      const std::int32_t index = offset + static_cast<std::int32_t>(i);
      const int l = left[i].get<int>();
      if (l < 0) {
        ensemble.nodes_.push_back(TreeNode::Leaf(index, value[i].get<float>()));
        continue;
      }
      const std::int32_t split = feature[i].get<std::int32_t>();
      Require(split >= 0 && split < ensemble.num_features_ && split < (1 << 30),
              "XGBoost split on feature {} of {}", split, ensemble.num_features_);
      const int r = right[i].get<int>();
      Require(static_cast<size_t>(l) < count && r >= 0 && static_cast<size_t>(r) < count,
              "XGBoost node {} of tree {} has children {} and {}: expected 0 to {}", i,
              ensemble.roots_.size(), l, r, count - 1);
      ensemble.nodes_.push_back(TreeNode::Split(split, default_left[i].get<int>() != 0,
                                                value[i].get<float>(), offset + l, offset + r));
    }
    ensemble.max_depth_ = std::max(
        ensemble.max_depth_, CheckedDepth(ensemble.nodes_, offset, count, ensemble.roots_.size()));
    ensemble.roots_.push_back(offset);
  }
  ensemble.BuildBitvectorTrees();
  return ensemble;
}

void FlatTreeEnsemble::BuildBitvectorTrees() {
  BitvectorTrees& trees = bitvector_trees_;
  trees = BitvectorTrees();
  constexpr int kMaxLeaves = 32;
  // In-order numbering: returns the leaves of the subtree as [first, end).
  std::function<std::pair<int, int>(std::int32_t, int)> number =
      [&](std::int32_t index, int next_leaf) -> std::pair<int, int> {
    const TreeNode& node = nodes_[index];
    if (node.is_leaf()) {
      trees.leaf_value.push_back(node.value);
      return {next_leaf, next_leaf + 1};
    }
    const std::pair<int, int> left = number(node.left, next_leaf);
    const std::pair<int, int> right = number(node.right, left.second);
    if (right.second <= kMaxLeaves) {
      std::uint32_t bits = ~0u;
      for (int leaf = left.first; leaf < left.second; ++leaf) bits &= ~(1u << leaf);
      trees.feature.push_back(node.feature());
      trees.threshold.push_back(node.value);
      trees.bitvector.push_back(bits);
      trees.default_left.push_back(node.default_left() ? 1 : 0);
    }
    return {left.first, right.second};
  };
  for (const std::int32_t root : roots_) {
    trees.node_begin.push_back(static_cast<std::int32_t>(trees.feature.size()));
    trees.leaf_begin.push_back(static_cast<std::int32_t>(trees.leaf_value.size()));
    if (number(root, 0).second > kMaxLeaves) return;  // not usable: Margin() row by row
  }
  trees.node_begin.push_back(static_cast<std::int32_t>(trees.feature.size()));
  trees.usable = true;
}

float FlatTreeEnsemble::Margin(const float* row) const {
  return RowMargin(nodes_.data(), roots_.data(), num_trees(), base_margin_, row);
}

namespace {

// Rows per block: two 512-bit vectors of floats (four 256-bit ones), few enough that a block's
// transposed rows (num_features x 32 floats) stay in L1. Each node's threshold, bitvector and
// feature are loaded once per block, so a wider block spends less on them per row; 32 rows still
// keep every lane's bits and sums in registers on AVX2. A row's sum is the same at any width.
constexpr int kBlockRows = 32;
constexpr int kAvx512Vectors = kBlockRows / 16;
constexpr int kAvx2Vectors = kBlockRows / 8;

}  // namespace

namespace {

// The trees' bitvector arrays, borrowed for one block.
struct BitvectorView {
  const std::int32_t* feature;
  const float* threshold;
  const std::uint32_t* bitvector;
  const std::uint8_t* default_left;
  const std::int32_t* node_begin;
  const std::int32_t* leaf_begin;
  const float* leaf_value;
  int trees;
};

// columns: (features, kBlockRows), lane r is row r. Adds each row's leaf values to sums[r] in
// tree order.
void BlockScalar(const BitvectorView& t, const float* columns, float* sums) {
  for (int tree = 0; tree < t.trees; ++tree) {
    std::uint32_t leaves[kBlockRows];
    for (std::uint32_t& bits : leaves) bits = ~0u;
    for (int node = t.node_begin[tree]; node < t.node_begin[tree + 1]; ++node) {
      const float* x = columns + t.feature[node] * kBlockRows;
      const float threshold = t.threshold[node];
      const std::uint32_t cleared = ~t.bitvector[node];
      const bool nan_left = t.default_left[node] != 0;
      for (int r = 0; r < kBlockRows; ++r) {
        const bool right = !(x[r] < threshold) && !(nan_left && std::isnan(x[r]));
        leaves[r] &= ~(cleared & (0u - static_cast<std::uint32_t>(right)));
      }
    }
    const float* values = t.leaf_value + t.leaf_begin[tree];
    for (int r = 0; r < kBlockRows; ++r) sums[r] += values[__builtin_ctz(leaves[r])];
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
#define CMBRL_HAVE_AVX512_TREES 1
// GCC 12 warns inside its own intrinsics (the "undefined" source of the gather).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
// The same with the rows in 16-lane AVX-512 registers: per test one compare into a lane mask and
// one masked AND; the exit leaf's index from the lowest set bit's float exponent; its value by
// a gather. Lane by lane the same float additions as BlockScalar.
__attribute__((target("avx512f"))) void BlockAvx512(const BitvectorView& t, const float* columns,
                                                    float* sums) {
  __m512 sum[kAvx512Vectors];
  for (int v = 0; v < kAvx512Vectors; ++v) sum[v] = _mm512_loadu_ps(sums + 16 * v);
  const __m512i all = _mm512_set1_epi32(-1);
  for (int tree = 0; tree < t.trees; ++tree) {
    __m512i leaves[kAvx512Vectors];
    for (__m512i& bits : leaves) bits = all;
    for (int node = t.node_begin[tree]; node < t.node_begin[tree + 1]; ++node) {
      const float* x = columns + t.feature[node] * kBlockRows;
      const __m512 threshold = _mm512_set1_ps(t.threshold[node]);
      const __m512i kept = _mm512_set1_epi32(static_cast<int>(t.bitvector[node]));
      const bool nan_left = t.default_left[node] != 0;
      for (int v = 0; v < kAvx512Vectors; ++v) {
        const __m512 value = _mm512_loadu_ps(x + 16 * v);
        __mmask16 right = _mm512_cmp_ps_mask(value, threshold, _CMP_NLT_UQ);
        if (nan_left) right &= _mm512_cmp_ps_mask(value, value, _CMP_ORD_Q);
        leaves[v] = _mm512_mask_and_epi32(leaves[v], right, leaves[v], kept);
      }
    }
    const float* values = t.leaf_value + t.leaf_begin[tree];
    for (int v = 0; v < kAvx512Vectors; ++v) {
      const __m512i lowest =
          _mm512_and_si512(leaves[v], _mm512_sub_epi32(_mm512_setzero_si512(), leaves[v]));
      const __m512i exponent =
          _mm512_srli_epi32(_mm512_castps_si512(_mm512_cvtepu32_ps(lowest)), 23);
      const __m512i index = _mm512_sub_epi32(exponent, _mm512_set1_epi32(127));
      sum[v] = _mm512_add_ps(sum[v], _mm512_i32gather_ps(index, values, 4));
    }
  }
  for (int v = 0; v < kAvx512Vectors; ++v) _mm512_storeu_ps(sums + 16 * v, sum[v]);
}

// The same on AVX2 CPUs, the rows in 8-lane registers. A compare gives all-ones lanes where
// the row goes right; the exit leaf's index comes from the lowest set bit converted to float
// (a signed conversion: bit 31 gives -2^31, whose exponent field is still 158 once the sign is
// masked off).
__attribute__((target("avx2"))) void BlockAvx2(const BitvectorView& t, const float* columns,
                                               float* sums) {
  __m256 sum[kAvx2Vectors];
  for (int v = 0; v < kAvx2Vectors; ++v) sum[v] = _mm256_loadu_ps(sums + 8 * v);
  const __m256i all = _mm256_set1_epi32(-1);
  const __m256i exponent_mask = _mm256_set1_epi32(0xff);
  const __m256i bias = _mm256_set1_epi32(127);
  for (int tree = 0; tree < t.trees; ++tree) {
    __m256i leaves[kAvx2Vectors];
    for (__m256i& bits : leaves) bits = all;
    for (int node = t.node_begin[tree]; node < t.node_begin[tree + 1]; ++node) {
      const float* x = columns + t.feature[node] * kBlockRows;
      const __m256 threshold = _mm256_set1_ps(t.threshold[node]);
      const __m256i cleared = _mm256_set1_epi32(static_cast<int>(~t.bitvector[node]));
      const bool nan_left = t.default_left[node] != 0;
      for (int v = 0; v < kAvx2Vectors; ++v) {
        const __m256 value = _mm256_loadu_ps(x + 8 * v);
        __m256 right = _mm256_cmp_ps(value, threshold, _CMP_NLT_UQ);
        if (nan_left) right = _mm256_and_ps(right, _mm256_cmp_ps(value, value, _CMP_ORD_Q));
        leaves[v] =
            _mm256_andnot_si256(_mm256_and_si256(_mm256_castps_si256(right), cleared), leaves[v]);
      }
    }
    const float* values = t.leaf_value + t.leaf_begin[tree];
    for (int v = 0; v < kAvx2Vectors; ++v) {
      const __m256i lowest =
          _mm256_and_si256(leaves[v], _mm256_sub_epi32(_mm256_setzero_si256(), leaves[v]));
      const __m256i exponent = _mm256_and_si256(
          _mm256_srli_epi32(_mm256_castps_si256(_mm256_cvtepi32_ps(lowest)), 23), exponent_mask);
      const __m256i index = _mm256_sub_epi32(exponent, bias);
      sum[v] = _mm256_add_ps(sum[v], _mm256_i32gather_ps(values, index, 4));
    }
  }
  for (int v = 0; v < kAvx2Vectors; ++v) _mm256_storeu_ps(sums + 8 * v, sum[v]);
}
#pragma GCC diagnostic pop
#endif

}  // namespace

void FlatTreeEnsemble::MarginsOfBlock(const float* rows, int count, float* columns, BlockIsa isa,
                                      float* out) const {
  const BitvectorTrees& trees = bitvector_trees_;
  const int features = num_features_;
  // Missing rows of a short block repeat row 0; their sums are dropped.
  for (int r = 0; r < kBlockRows; ++r) {
    const float* row = rows + static_cast<std::int64_t>(r < count ? r : 0) * features;
    for (int f = 0; f < features; ++f) columns[f * kBlockRows + r] = row[f];
  }
  const BitvectorView view{trees.feature.data(),    trees.threshold.data(),
                           trees.bitvector.data(),  trees.default_left.data(),
                           trees.node_begin.data(), trees.leaf_begin.data(),
                           trees.leaf_value.data(), num_trees()};
  float sums[kBlockRows];
  for (float& sum : sums) sum = base_margin_;
#ifdef CMBRL_HAVE_AVX512_TREES
  if (isa == BlockIsa::kAvx512) {
    BlockAvx512(view, columns, sums);
  } else if (isa == BlockIsa::kAvx2) {
    BlockAvx2(view, columns, sums);
  } else {
    BlockScalar(view, columns, sums);
  }
#else
  (void)isa;
  BlockScalar(view, columns, sums);
#endif
  for (int r = 0; r < count; ++r) out[r] = sums[r];
}

void FlatTreeEnsemble::Margins(const float* rows, std::int64_t count, float* out, int threads,
                               TreeKernel kernel) const {
  if (!bitvector_trees_.usable || kernel == TreeKernel::kRowByRow) {
    for (std::int64_t i = 0; i < count; ++i) out[i] = Margin(rows + i * num_features_);
    return;
  }
  const std::int64_t blocks = (count + kBlockRows - 1) / kBlockRows;
  BlockIsa isa = BlockIsa::kPortable;
  if (kernel == TreeKernel::kFastest && CpuHasAvx512()) {
    isa = BlockIsa::kAvx512;
  } else if ((kernel == TreeKernel::kFastest || kernel == TreeKernel::kAvx2) && CpuHasAvx2()) {
    isa = BlockIsa::kAvx2;
  }
  const auto run_blocks = [&](std::int64_t begin, std::int64_t end) {
    std::vector<float> columns(static_cast<size_t>(num_features_) * kBlockRows);
    for (std::int64_t block = begin; block < end; ++block) {
      const std::int64_t first = block * kBlockRows;
      const int block_rows = static_cast<int>(std::min<std::int64_t>(kBlockRows, count - first));
      MarginsOfBlock(rows + first * num_features_, block_rows, columns.data(), isa, out + first);
    }
  };
  const int most = threads > 0 ? threads : CoreCount();
  // A thread is worth its start only for some 400k tree evaluations (about half a millisecond).
  const int workers = static_cast<int>(std::clamp<std::int64_t>(
      std::min<std::int64_t>(count * num_trees() / 400000, blocks), 1, most));
  ParallelRanges(blocks, workers, run_blocks);
}

}  // namespace cmbrl

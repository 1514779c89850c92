// A trained gradient-boosted tree ensemble as compact flat arrays, for fast batched prediction
// without XGBoost's general-purpose API (paper Section IV-A; the planner classifies tens of
// thousands of predicted states per step).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cmbrl {

// One node. Inner nodes send x[feature] < threshold to `left`, anything else (NaN included) to
// `right` or `left` per default_left; leaves have feature -1 and carry their value.
struct TreeNode {
  std::int32_t feature = -1;
  float value = 0.0f;       // split threshold (inner) or leaf value (leaf)
  std::int32_t left = -1;   // absolute node index
  std::int32_t right = -1;  // absolute node index
  bool default_left = false;
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

  // Margin (log-odds) of one row of num_features() floats.
  float Margin(const float* row) const;

  // Margins of `rows` rows (row-major), written to `out`.
  void Margins(const float* rows, std::int64_t count, float* out) const;

  int num_trees() const { return static_cast<int>(roots_.size()); }
  int num_features() const { return num_features_; }
  int max_depth() const { return max_depth_; }  // edges from a root to its deepest leaf
  float base_margin() const { return base_margin_; }
  const std::vector<TreeNode>& nodes() const { return nodes_; }
  const std::vector<std::int32_t>& roots() const { return roots_; }

 private:
  std::vector<TreeNode> nodes_;
  std::vector<std::int32_t> roots_;
  int num_features_ = 0;
  int max_depth_ = 0;
  float base_margin_ = 0.0f;
};

}  // namespace cmbrl

#include "cmbrl/models/tree_ensemble.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

using Json = nlohmann::json;

const Json& Field(const Json& object, const char* key, const char* where) {
  Require(object.is_object() && object.contains(key),
          "XGBoost model JSON has no '{}' in {}: expected a model saved by XGBoost 1.x", key,
          where);
  return object.at(key);
}

// Depth of the subtree under `node` (a leaf has depth 0).
int Depth(const std::vector<TreeNode>& nodes, std::int32_t node) {
  if (nodes[node].feature < 0) return 0;
  return 1 + std::max(Depth(nodes, nodes[node].left), Depth(nodes, nodes[node].right));
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
    for (size_t i = 0; i < count; ++i) {
      TreeNode node;
      node.value = value[i].get<float>();
      const int l = left[i].get<int>();
      if (l >= 0) {
        node.feature = feature[i].get<std::int32_t>();
        Require(node.feature < ensemble.num_features_, "XGBoost split on feature {} of {}",
                node.feature, ensemble.num_features_);
        node.left = offset + l;
        node.right = offset + right[i].get<std::int32_t>();
        node.default_left = default_left[i].get<int>() != 0;
      }
      ensemble.nodes_.push_back(node);
    }
    ensemble.roots_.push_back(offset);
    ensemble.max_depth_ = std::max(ensemble.max_depth_, Depth(ensemble.nodes_, offset));
  }
  return ensemble;
}

float FlatTreeEnsemble::Margin(const float* row) const {
  float sum = base_margin_;
  const TreeNode* nodes = nodes_.data();
  for (const std::int32_t root : roots_) {
    const TreeNode* node = nodes + root;
    while (node->feature >= 0) {
      const float x = row[node->feature];
      const bool go_left = std::isnan(x) ? node->default_left : x < node->value;
      node = nodes + (go_left ? node->left : node->right);
    }
    sum += node->value;
  }
  return sum;
}

void FlatTreeEnsemble::Margins(const float* rows, std::int64_t count, float* out) const {
  for (std::int64_t i = 0; i < count; ++i) out[i] = Margin(rows + i * num_features_);
}

}  // namespace cmbrl

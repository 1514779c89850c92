// The constraint classifier of the paper (Section IV-A, appendix "Training detail"; facts B4):
// gradient-boosted trees on the next state, with XGBoost set to mirror the paper's LightGBM.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/models/cost_model.h"
#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/model_options.h"
#include "cmbrl/models/tree_ensemble.h"

namespace cmbrl {

// What one fit did. Accuracies are over the states the fit used.
struct CostFitReport {
  int safe_used = 0;
  int unsafe_used = 0;
  bool trained = false;          // false until at least one unsafe state was seen
  double safe_accuracy = 0.0;    // fraction of safe states classified safe
  double unsafe_accuracy = 0.0;  // recall of the unsafe class (NaN with no unsafe state)
  int trees = 0;
  double seconds = 0.0;
  bool interrupted = false;      // keep_going said stop: the model is as it was before the fit
};

// XGBoost binary classifier retrained from scratch at every fit; predictions go through the
// exported flat trees (host) or their tensors (device), never row by row through XGBoost. Until
// a fit has seen an unsafe state every state is predicted safe: with no violation observed there
// is nothing to avoid yet. Predictions are safe to call concurrently; Fit and Load are not.
class XgbCostModel final : public CostModel {
 public:
  // Throws cmbrl::Error for bad options or an unavailable device.
  XgbCostModel(int state_dim, XgbCostModelOptions options, std::uint64_t seed);
  ~XgbCostModel() override;

  int state_dim() const override { return state_dim_; }
  const XgbCostModelOptions& options() const { return options_; }
  bool trained() const { return trained_; }

  // The states a fit uses from a buffer (the fit set): every unsafe state, oldest first, and
  // safe_per_unsafe * n_unsafe + 1 safe states chosen by safe_selection. Row-major floats.
  struct FitSet {
    std::vector<float> safe, unsafe;  // (safe_count, S), (unsafe_count, S)
    int safe_count = 0, unsafe_count = 0;
  };
  FitSet SelectFitSet(const LabeledStateBuffer& data) const;

  // A fit on SelectFitSet(data). `keep_going` as FitArrays's.
  CostFitReport Fit(const LabeledStateBuffer& data,
                    const std::function<bool()>& keep_going = nullptr);

  // The same from arrays: (safe_count, S) and (unsafe_count, S) row-major floats. `keep_going`,
  // when given, is asked after each boosting round: false abandons the fit there, leaving the
  // model as it was (a fit starts from scratch, so half of one is no model), and the report
  // says interrupted.
  CostFitReport FitArrays(const float* safe, int safe_count, const float* unsafe, int unsafe_count,
                          const std::function<bool()>& keep_going = nullptr);

  torch::Tensor PredictViolation(const torch::Tensor& states) const override;
  std::vector<std::uint8_t> PredictRows(const float* states, int rows) const override;

  // Log-odds of a violation per row through the flat trees, and through XGBoost's own predictor
  // (for checks; slow). Both need a trained model.
  std::vector<float> Margins(const float* states, int rows) const;
  std::vector<float> XgboostMargins(const float* states, int rows) const;

  const FlatTreeEnsemble& trees() const { return trees_; }

  // The booster (XGBoost's JSON) and its state dimension in one JSON file; the options (the
  // threshold among them) stay this model's. Load checks the state dimension and throws
  // cmbrl::Error naming a mismatch.
  void Save(const std::string& path) const;
  void Load(const std::string& path);

 private:
  struct Booster;
  class DeviceTrees;

  void AdoptBoosterJson(const std::string& json);
  // Back to the untrained state, which predicts every state safe (no unsafe state seen yet).
  void Untrain();

  int state_dim_;
  XgbCostModelOptions options_;
  std::uint64_t seed_;
  bool trained_ = false;
  float margin_threshold_ = 0.0f;  // violation when margin > this (logit of the threshold)
  std::unique_ptr<Booster> booster_;
  FlatTreeEnsemble trees_;
  std::unique_ptr<DeviceTrees> device_trees_;
};

}  // namespace cmbrl

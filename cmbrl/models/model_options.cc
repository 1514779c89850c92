#include "cmbrl/models/model_options.h"

#include <cmath>

#include "cmbrl/core/check.h"

namespace cmbrl {

void ValidateStepModelOptions(const StepModelOptions& o) {
  Require(!o.hidden_sizes.empty() && o.hidden_sizes.size() <= 16,
          "hidden_sizes has {} layers: expected 1 to 16", o.hidden_sizes.size());
  for (const int width : o.hidden_sizes) {
    Require(width >= 1 && width <= 65536, "hidden_sizes holds {}: expected widths of 1 to 65536",
            width);
  }
  Require(o.learning_rate > 0 && o.learning_rate <= 1,
          "learning_rate is {}: expected a number in (0, 1]", o.learning_rate);
  Require(o.batch_size >= 1 && o.batch_size <= 1'000'000, "batch_size is {}: expected 1 to 1000000",
          o.batch_size);
  Require(o.max_epochs >= 1 && o.max_epochs <= 100'000, "max_epochs is {}: expected 1 to 100000",
          o.max_epochs);
  Require(o.validation_fraction > 0 && o.validation_fraction < 1,
          "validation_fraction is {}: expected a number in (0, 1)", o.validation_fraction);
  Require(o.patience >= 1 && o.patience <= 100'000, "patience is {}: expected 1 to 100000",
          o.patience);
}

void ValidateEnsembleOptions(const EnsembleOptions& o) {
  // Upper bounds keep a typing slip from allocating the machine away or running for ever.
  Require(o.ensemble_size >= 1 && o.ensemble_size <= 64,
          "ensemble_size is {}: expected 1 to 64 members", o.ensemble_size);
  // No hidden layer would make a linear model, which is not the paper's and never meant.
  Require(!o.hidden_sizes.empty() && o.hidden_sizes.size() <= 16,
          "hidden_sizes has {} layers: expected 1 to 16", o.hidden_sizes.size());
  for (size_t i = 0; i < o.hidden_sizes.size(); ++i) {
    Require(o.hidden_sizes[i] >= 1 && o.hidden_sizes[i] <= 65536,
            "hidden_sizes[{}] is {}: expected a width from 1 to 65536", i, o.hidden_sizes[i]);
  }
  // Upper bounds here and below: values no one means (an Adam step of 1e300 trains to NaN).
  Require(o.learning_rate > 0 && o.learning_rate <= 1,
          "learning_rate is {}: expected a number in (0, 1]", o.learning_rate);
  Require(o.batch_size >= 1 && o.batch_size <= 10'000'000,
          "batch_size is {}: expected 1 to 10000000", o.batch_size);
  Require(o.max_epochs >= 1 && o.max_epochs <= 100'000,
          "max_epochs is {}: expected 1 to 100000", o.max_epochs);
  Require(o.validation_fraction >= 0 && o.validation_fraction < 1,
          "validation_fraction is {}: expected a number in [0, 1)", o.validation_fraction);
  Require(o.member_subset_fraction > 0 && o.member_subset_fraction <= 1,
          "member_subset_fraction is {}: expected a number in (0, 1]", o.member_subset_fraction);
  Require(o.validate_every >= 1 && o.validate_every <= 100'000,
          "validate_every is {}: expected 1 to 100000 epochs", o.validate_every);
  Require(o.patience >= 1 && o.patience <= 100'000, "patience is {}: expected 1 to 100000",
          o.patience);
  Require(o.init_std > 0 && o.init_std <= 10, "init_std is {}: expected a number in (0, 10]",
          o.init_std);
  Require(o.min_std >= 0 && o.min_std <= 10, "min_std is {}: expected a number in [0, 10]",
          o.min_std);
  Require(o.precision == "fp32" || o.precision == "tf32" || o.precision == "bf16",
          "precision is '{}': expected fp32, tf32 or bf16", o.precision);
  Require(o.precision != "tf32" || o.device.rfind("cuda", 0) == 0,
          "precision is tf32 but device is '{}': TF32 is a CUDA tensor-core format; use fp32 or "
          "bf16 on the CPU",
          o.device);
  Require(o.backend == "auto" || o.backend == "libtorch" || o.backend == "onednn",
          "backend is '{}': expected auto, libtorch or onednn", o.backend);
  Require(o.backend != "onednn" || o.device == "cpu",
          "backend is onednn but device is '{}': oneDNN predicts on the CPU; use libtorch or auto "
          "on CUDA",
          o.device);
}

void ValidateXgbCostModelOptions(const XgbCostModelOptions& o) {
  Require(o.rounds >= 1 && o.rounds <= 100'000, "rounds is {}: expected 1 to 100000", o.rounds);
  Require(o.learning_rate > 0 && o.learning_rate <= 1,
          "learning_rate is {}: expected a number in (0, 1]", o.learning_rate);
  Require(o.max_depth >= 1 && o.max_depth <= 64, "max_depth is {}: expected 1 to 64",
          o.max_depth);
  Require(o.max_leaves >= 2 && o.max_leaves <= 1'000'000,
          "max_leaves is {}: expected 2 to 1000000", o.max_leaves);
  Require(o.grow_policy == "lossguide" || o.grow_policy == "depthwise",
          "grow_policy is '{}': expected 'lossguide' or 'depthwise'", o.grow_policy);
  Require(o.tree_method == "hist" || o.tree_method == "approx" || o.tree_method == "exact",
          "tree_method is '{}': expected 'hist', 'approx' or 'exact'", o.tree_method);
  // Named here rather than by XGBoost, which refuses some values at the first fit under its own
  // parameter names, and takes others to trees that never split.
  Require(o.l2_regularization >= 0 && o.l2_regularization <= 1e6,
          "l2_regularization is {}: expected a number in [0, 1e6]", o.l2_regularization);
  Require(o.min_child_weight >= 0 && o.min_child_weight <= 1e6,
          "min_child_weight is {}: expected a number in [0, 1e6]", o.min_child_weight);
  Require(o.threshold > 0 && o.threshold < 1, "threshold is {}: expected a probability in (0, 1)",
          o.threshold);
  Require(o.safe_per_unsafe >= 0 && o.safe_per_unsafe <= 1000,
          "safe_per_unsafe is {}: expected 0 to 1000", o.safe_per_unsafe);
  Require(o.safe_selection == "storage_order" || o.safe_selection == "newest",
          "safe_selection is '{}': expected 'storage_order' or 'newest'", o.safe_selection);
  Require(o.threads >= 0 && o.threads <= 1024,
          "threads is {}: expected 0 (one per core) to 1024", o.threads);
  Require(o.predict_threads >= 0 && o.predict_threads <= 1024,
          "predict_threads is {}: expected 0 (one per core) to 1024", o.predict_threads);
}

double EnsembleParameterBytes(const EnsembleOptions& options, int state_dim, int action_dim) {
  double parameters = 0.0;
  double in = static_cast<double>(state_dim) + action_dim;
  for (const int width : options.hidden_sizes) {
    parameters += (in + 1) * width;
    in = width;
  }
  parameters += (in + 1) * state_dim;
  return static_cast<double>(options.ensemble_size) * 4.0 * parameters * sizeof(float);
}

}  // namespace cmbrl

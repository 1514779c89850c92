// The learned models' options as plain data, with their checks: the dynamics ensemble's and the
// constraint classifier's. Free of LibTorch and XGBoost, so that configuration, sweeps and
// reports can read and check them without linking the models.
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

struct EnsembleOptions {
  int ensemble_size = 4;                               // E: 4 for Point, 5 for Car in the paper
  std::vector<int> hidden_sizes = {1024, 1024, 1024};  // ReLU hidden layers
  bool predict_delta = false;           // false: absolute next state (paper); true: the change
  double learning_rate = 1e-3;          // Adam
  int batch_size = 256;                 // per member per step
  int max_epochs = 70;                  // per fit
  double validation_fraction = 0.15;    // held out by a fresh random split at every fit
  double member_subset_fraction = 0.8;  // each member's fresh share of the train split per epoch
  int validate_every = 5;               // epochs between validation checks
  int patience = 5;                     // checks without improvement before stopping
  double init_std = 0.02;               // weights start as N(0, init_std); biases as PyTorch's
  double min_std = 1e-3;                // normaliser: smaller standard deviations become 1
  std::string device = "cpu";           // "cpu", "cuda" or "cuda:i"
  // Arithmetic of the predictions' matrix products; never reduced unless asked for:
  //   fp32: float32 throughout;
  //   tf32: CUDA only; cuBLAS's TF32 tensor cores for every float32 product of the process,
  //         training included (10-bit mantissa inputs, float32 sums);
  //   bf16: predictions with bfloat16 copies of the weights and activations (8-bit mantissa),
  //         refreshed after every fit; training stays float32.
  std::string precision = "fp32";
  // Who computes the predictions and the training products:
  //   auto: onednn where it is available (a build with oneDNN, device cpu, fp32, or bf16 on a
  //         CPU with AVX-512), libtorch elsewhere; the training products through onednn at
  //         any width on a CPU with AVX-512, elsewhere only where every hidden layer is at most
  //         256 wide (wider, OpenBLAS was faster there);
  //   libtorch: LibTorch's batched products and autograd (OpenBLAS for fp32 on the CPU; cuBLAS
  //         on CUDA);
  //   onednn: oneDNN's matrix-product primitives for both (onednn_forward.h,
  //         onednn_training.h); an error where unavailable.
  std::string backend = "auto";
};

// Throws cmbrl::Error naming the first field with a bad value.
void ValidateEnsembleOptions(const EnsembleOptions& options);

// Bytes the ensemble's parameters take while it trains: every member's weights, their gradients
// and Adam's two moments (float32), for states of `state_dim` and actions of `action_dim`.
double EnsembleParameterBytes(const EnsembleOptions& options, int state_dim, int action_dim);

// A learned step signal (step_model.h): the reward of objective.reward: learned (keys
// reward_model.*) or the termination of objective.termination: learned (termination_model.*), an
// MLP from the step (state, action, next state), refitted from scratch with the dynamics.
struct StepModelOptions {
  std::vector<int> hidden_sizes = {200, 200};  // ReLU hidden layers
  double learning_rate = 1e-3;                 // Adam
  int batch_size = 256;
  int max_epochs = 50;                // per fit
  double validation_fraction = 0.15;  // held out by a fresh random split at every fit
  int patience = 5;                   // epochs without improvement before stopping
};

// Throws cmbrl::Error naming the first field with a bad value.
void ValidateStepModelOptions(const StepModelOptions& options);

struct XgbCostModelOptions {
  int rounds = 400;            // trees (LightGBM n_estimators)
  double learning_rate = 0.3;  // eta
  int max_depth = 8;
  int max_leaves = 12;                    // LightGBM num_leaves
  std::string grow_policy = "lossguide";  // leaf-wise growth, as LightGBM
  std::string tree_method = "hist";
  double l2_regularization = 0.0;  // XGBoost lambda; LightGBM's lambda_l2 default is 0
  double min_child_weight = 1e-3;  // LightGBM's min_sum_hessian_in_leaf
  bool boost_from_average = true;  // start from the unsafe fraction (LightGBM's default)
  double threshold = 0.5;          // violation when the probability exceeds this
  int safe_per_unsafe = 3;         // a fit uses at most safe_per_unsafe * n_unsafe + 1 safe
  // Which safe states a fit takes: "storage_order", the last slots of the safe ring as the
  // original does (old states once the ring has wrapped), or "newest".
  std::string safe_selection = "storage_order";
  // XGBoost threads while fitting; 0: one per core this process may use. The trees are the same
  // on any count (tested), so the original's n_jobs 1 is kept in results, not in speed.
  int threads = 0;
  int predict_threads = 0;         // threads of the host tree walk; 0: one per core
  std::string device = "cpu";      // where PredictViolation evaluates tensors
};

// Throws cmbrl::Error naming the first field with a bad value.
void ValidateXgbCostModelOptions(const XgbCostModelOptions& options);

}  // namespace cmbrl

// The dynamics ensemble of the paper (Section IV-A and appendix "Training detail"; facts B3): E
// MLPs from (state, action) to next state, evaluated together with batched matrix products.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/models/dynamics_model.h"
#include "cmbrl/models/model_options.h"
#include "cmbrl/models/transition_buffer.h"

namespace cmbrl {

// What one fit did. MSEs are in normalised target units, averaged over members.
struct EnsembleFitReport {
  int epochs = 0;
  int train_size = 0;
  int validation_size = 0;
  double train_mse = 0.0;            // last epoch, over the members' subsets
  double validation_mse = 0.0;       // last check (NaN when nothing was held out)
  double best_validation_mse = 0.0;  // best check of this fit
  bool stopped_early = false;
  bool interrupted = false;  // keep_going said stop
  bool paused = false;       // pause_due said pause: the fit is open (see Fit)
  double seconds = 0.0;
};

// The ensemble. Weights live as stacked (E, in, out) tensors on one device; Predict runs all
// members in one batched pass. Fit trains every member in the same batched step with Adam,
// warm-starting from the previous fit (weights and optimiser state). Predict is safe to call
// concurrently; Fit, Load and Save are not, with each other or with Predict.
class EnsembleDynamics final : public DynamicsModel {
 public:
  // Throws cmbrl::Error for bad options, an unavailable device or an unavailable backend (oneDNN
  // not built, or its bf16 on a CPU without AVX-512). `seed` drives weight
  // initialisation, the data splits and the minibatch order.
  EnsembleDynamics(int state_dim, int action_dim, EnsembleOptions options, std::uint64_t seed);
  ~EnsembleDynamics() override;

  int state_dim() const override { return state_dim_; }
  int action_dim() const override { return action_dim_; }
  int ensemble_size() const override { return options_.ensemble_size; }
  const EnsembleOptions& options() const { return options_; }
  // The backend `options().backend` resolved to here, for the predictions and for the training
  // products: "onednn" or "libtorch" each (model_options.h says when they differ).
  const std::string& backend() const { return backend_; }
  std::string training_backend() const;

  torch::Tensor Predict(const torch::Tensor& states, const torch::Tensor& actions) const override;
  torch::Tensor PredictUnchecked(const torch::Tensor& states,
                                 const torch::Tensor& actions) const override;

  // Recomputes the normalisers over the whole buffer, then trains (facts B3). Throws
  // cmbrl::Error when the buffer has fewer than 2 transitions or other dimensions.
  // `keep_going`, when given, is asked after each epoch: false stops the fit there, keeping the
  // epochs done (report.interrupted; a Python caller's Ctrl-C).
  // `pause_due`, when given, is asked after each epoch that does not end the fit: true leaves
  // the fit open there (report.paused) with the epochs done. Save keeps its place, and the next
  // Fit, on the same data (Load between them allowed), goes on from there to the model an
  // uninterrupted fit gives; its report covers the whole fit. Throws cmbrl::Error when an open
  // fit is given other data.
  EnsembleFitReport Fit(const TransitionBuffer& data,
                        const std::function<bool()>& keep_going = nullptr,
                        const std::function<bool()>& pause_due = nullptr);
  // Whether a fit is open (paused by pause_due and not yet finished).
  bool fit_open() const;

  // Weights, normalisers, optimiser state and generator state, in one file. Load checks that
  // the file matches this ensemble's dimensions and throws cmbrl::Error naming the difference.
  void Save(const std::string& path) const;
  void Load(const std::string& path);

  // Normalisers, for inspection and tests: inputs are [state, action], targets the next state
  // (or its change).
  torch::Tensor NormalizeInputs(const torch::Tensor& inputs) const;
  torch::Tensor DenormalizeInputs(const torch::Tensor& normalized) const;

  // Floating-point operations of one Predict over E x `samples` rows (multiply-adds count 2).
  double PredictFlops(std::int64_t samples) const;

 private:
  struct State;

  // `prediction`: use the prediction precision's weights (bf16 copies) rather than float32.
  torch::Tensor Forward(const torch::Tensor& normalized_inputs, bool prediction) const;
  void RefreshPredictionWeights();  // after the weights change (construction, Fit, Load)
  // One epoch of Fit: each member's own fresh subset of `subset` of the train rows (train_rows,
  // (T)) in batches, one optimiser step each, over the normalised inputs x and targets y; the
  // epoch's train MSE per row and member.
  double TrainEpoch(const torch::Tensor& x, const torch::Tensor& y, const torch::Tensor& train_rows,
                    std::int64_t subset);

  int state_dim_;
  int action_dim_;
  EnsembleOptions options_;
  std::string backend_;
  std::unique_ptr<State> state_;
};

}  // namespace cmbrl

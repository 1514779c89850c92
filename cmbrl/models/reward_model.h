// A learned reward (objective.reward: learned): an MLP from a step's inputs, the state, action
// and next state side by side, to the reward the environment gave for it. It is fitted on the
// run's stored transitions and refitted with the dynamics, each time from fresh weights drawn
// from its own generator; docs/CUSTOM_TASKS.md says why it is a model of its own rather than
// an extra output of each dynamics member.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/models/model_options.h"
#include "cmbrl/models/transition_buffer.h"

namespace cmbrl {

// What one fit did; MSEs in the reward's units squared.
struct RewardFitReport {
  int epochs = 0;
  int train_size = 0;
  int validation_size = 0;
  double train_mse = 0.0;       // the last epoch's
  double validation_mse = 0.0;  // of the weights kept (the best epoch's)
  double seconds = 0.0;
};

// Not thread-safe; Predict may be called concurrently with itself.
class RewardModel {
 public:
  // Throws cmbrl::Error for bad options or an input width below 1. `seed` drives the weights,
  // the splits and the minibatch order.
  RewardModel(int input_dim, RewardModelOptions options, std::uint64_t seed);
  ~RewardModel();

  int input_dim() const { return input_dim_; }
  const RewardModelOptions& options() const { return options_; }

  // Fits fresh weights to inputs (N, input_dim) and rewards (N), both float32 on the CPU,
  // holding out options().validation_fraction of the rows; keeps the epoch of least validation
  // error. Throws cmbrl::Error for fewer than 2 rows, other shapes or non-finite values.
  RewardFitReport Fit(const torch::Tensor& inputs, const torch::Tensor& rewards);
  bool fitted() const { return fitted_; }

  // (..., input_dim) float32 -> (...) float32, on the inputs' device. Before any fit: zeros.
  torch::Tensor Predict(const torch::Tensor& inputs) const;

  // Weights, normalisers and the generator, in one file; Load checks the widths and throws
  // cmbrl::Error naming the file and the difference.
  void Save(const std::string& path) const;
  void Load(const std::string& path);

 private:
  torch::Tensor Forward(const torch::Tensor& normalized) const;  // (N, in) -> (N)
  // One pass over the `train` rows of normalised x and y in shuffled minibatches, an optimiser
  // step each; their mean squared error in normalised units.
  double TrainEpoch(torch::optim::Optimizer& optimiser, const torch::Tensor& x,
                    const torch::Tensor& y, const torch::Tensor& train);
  void InitialiseWeights();

  int input_dim_;
  RewardModelOptions options_;
  at::Generator generator_;
  std::vector<torch::Tensor> weights_, biases_;
  torch::Tensor input_mean_, input_std_, reward_mean_, reward_std_;
  bool fitted_ = false;
};

// The reward model's inputs for a buffer's stored transitions: (size, S + A + S) rows of state,
// action and next state; and their rewards (size). Throws cmbrl::Error for a buffer that keeps
// no rewards.
torch::Tensor RewardInputs(const TransitionBuffer& buffer);
torch::Tensor StoredRewards(const TransitionBuffer& buffer);

// The same rows for predicted steps: states (..., S), actions (..., A), next states (..., S)
// side by side as (..., S + A + S).
torch::Tensor RewardInputs(const torch::Tensor& states, const torch::Tensor& actions,
                           const torch::Tensor& next_states);

}  // namespace cmbrl

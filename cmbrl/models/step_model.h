// A learned per-step signal of a task: an MLP from a step's inputs, the state, action and next
// state side by side, to what the environment gave for that step. Two signals use it:
// - the reward (objective.reward: learned), fitted as a regression (mean squared error);
// - the termination (objective.termination: learned), fitted as a classification (binary cross
//   entropy), predicting the probability that the step ends the episode.
// It is fitted on the run's stored transitions and refitted with the dynamics, each time from
// fresh weights drawn from its own generator; docs/CUSTOM_TASKS.md says why it is a model of its
// own rather than an extra output of each dynamics member.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/models/model_options.h"
#include "cmbrl/models/transition_buffer.h"

namespace cmbrl {

// What a StepModel learns.
enum class StepSignal {
  kReward,       // a real number per step
  kTermination,  // 1 where the step ended the episode, else 0
};

// "reward" or "termination": how files and messages name a signal.
const char* StepSignalName(StepSignal signal);

// What one fit did. The losses: a reward's mean squared error (its units squared); a
// termination's mean binary cross entropy (nats).
struct StepFitReport {
  int epochs = 0;
  int train_size = 0;
  int validation_size = 0;
  double train_loss = 0.0;       // the last epoch's
  double validation_loss = 0.0;  // of the weights kept (the best epoch's)
  double seconds = 0.0;
};

// Not thread-safe; Predict may be called concurrently with itself.
class StepModel {
 public:
  // Throws cmbrl::Error for bad options or an input width below 1. `seed` drives the weights,
  // the splits and the minibatch order.
  StepModel(StepSignal signal, int input_dim, StepModelOptions options, std::uint64_t seed);
  ~StepModel();

  StepSignal signal() const { return signal_; }
  int input_dim() const { return input_dim_; }
  const StepModelOptions& options() const { return options_; }

  // Fits fresh weights to inputs (N, input_dim) and targets (N), both float32 on the CPU
  // (a termination's targets 0 or 1), holding out options().validation_fraction of the rows;
  // keeps the epoch of least validation loss. Throws cmbrl::Error for fewer than 2 rows, other
  // shapes, non-finite values or a termination target other than 0 and 1.
  StepFitReport Fit(const torch::Tensor& inputs, const torch::Tensor& targets);
  bool fitted() const { return fitted_; }

  // (..., input_dim) float32 -> (...) float32, on the inputs' device: the reward, or the
  // probability that the step ends the episode. Before any fit: zeros.
  torch::Tensor Predict(const torch::Tensor& inputs) const;

  // Weights, normalisers and the generator, in one file; Load checks the signal and the widths
  // and throws cmbrl::Error naming the file and the difference.
  void Save(const std::string& path) const;
  void Load(const std::string& path);

 private:
  torch::Tensor Forward(const torch::Tensor& normalized) const;  // (N, in) -> (N)
  // The signal's loss of outputs against normalised targets: squared error or cross entropy.
  torch::Tensor Loss(const torch::Tensor& outputs, const torch::Tensor& targets) const;
  // One pass over the `train` rows of normalised x and y in shuffled minibatches, an optimiser
  // step each; their mean loss in normalised units.
  double TrainEpoch(torch::optim::Optimizer& optimiser, const torch::Tensor& x,
                    const torch::Tensor& y, const torch::Tensor& train);
  void InitialiseWeights();

  StepSignal signal_;
  int input_dim_;
  StepModelOptions options_;
  at::Generator generator_;
  std::vector<torch::Tensor> weights_, biases_;
  // A reward's targets are standardised; a termination's are not (mean 0, deviation 1).
  torch::Tensor input_mean_, input_std_, target_mean_, target_std_;
  bool fitted_ = false;
};

// The step model's inputs for a buffer's stored transitions: (size, S + A + S) rows of state,
// action and next state; their rewards (size); and their terminations (size, 0 or 1). Throw
// cmbrl::Error for a buffer that keeps no rewards, or no terminations.
torch::Tensor StepInputs(const TransitionBuffer& buffer);
torch::Tensor StoredRewards(const TransitionBuffer& buffer);
torch::Tensor StoredTerminations(const TransitionBuffer& buffer);

// The same rows for predicted steps: states (..., S), actions (..., A), next states (..., S)
// side by side as (..., S + A + S).
torch::Tensor StepInputs(const torch::Tensor& states, const torch::Tensor& actions,
                         const torch::Tensor& next_states);

}  // namespace cmbrl

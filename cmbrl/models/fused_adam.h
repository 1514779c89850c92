// Adam (Kingma and Ba, 2015) over a few large stacked parameter tensors, as the ensemble trains
// them (facts B3: learning rate 1e-3, PyTorch's default betas and epsilon). LibTorch 1.13's
// torch::optim::Adam makes about a dozen passes over memory per parameter and step, which took
// a third of a paper-sized training epoch on the CPU; this one makes one pass, on every core.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

namespace cmbrl {

struct FusedAdamOptions {
  double learning_rate = 1e-3;
  double beta1 = 0.9;
  double beta2 = 0.999;
  double epsilon = 1e-8;
};

// How many threads Step() splits a parameter of `elements` values over on the CPU: every core
// the process may use from 2^18 values on, else one (a thread's start costs tens of us).
int FusedAdamWorkers(std::int64_t elements);

// Owns the moments, borrows the parameters (float32, contiguous, one device). Step() reads each
// parameter's gradient and then drops it, so that the next backward pass writes a fresh
// gradient instead of adding to a zeroed one. Not thread-safe; the result does not depend on
// the number of threads.
class FusedAdam {
 public:
  FusedAdam(std::vector<torch::Tensor> parameters, FusedAdamOptions options);

  // One update of every parameter that has a gradient.
  void Step();

  // The same update made in parts, so that each part can run on the thread that made its
  // gradients while other threads still make theirs (the ensemble's members: one memory-bound
  // update beside another member's matrix products, instead of a pass of its own after them all).
  // BeginStep() once; StepPart(k, parts) for every k in [0, parts), from any threads at once; then
  // EndStep(). Part k is the k-th of `parts` equal slices along every parameter's first dimension
  // (the members of (E, ...) parameters), which `parts` must divide. Gives Step()'s bits. CPU
  // parameters only; a part's gradients must be complete when StepPart() runs and stay set until
  // EndStep(), which drops them.
  void BeginStep();
  void StepPart(std::int64_t part, std::int64_t parts);
  void EndStep();

  std::int64_t steps() const { return steps_; }

  // Moments and step count into / from an archive (checked against the parameters' shapes).
  void Save(torch::serialize::OutputArchive& archive) const;
  void Load(torch::serialize::InputArchive& archive, const std::string& source);

 private:
  std::vector<torch::Tensor> parameters_;
  std::vector<torch::Tensor> exp_avg_;     // first moments, like parameters_
  std::vector<torch::Tensor> exp_avg_sq_;  // second moments, like parameters_
  FusedAdamOptions options_;
  std::int64_t steps_ = 0;
  bool in_step_ = false;  // between BeginStep() and EndStep()
};

}  // namespace cmbrl

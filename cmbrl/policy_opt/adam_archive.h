// An Adam optimiser's moments in a checkpoint archive (the model-free learners' networks.pt),
// keyed by each parameter's place in the optimiser's one parameter group. LibTorch's own save
// keys them by the tensor's address, which differs from run to run, so two runs with the same
// numbers wrote different bytes; this form is the same bytes. Earlier builds' checkpoints, in
// LibTorch's form, are still read.
#pragma once

#include <torch/torch.h>

#include <string>

namespace cmbrl {

// Writes `optimizer`'s moments (step, exp_avg, exp_avg_sq, max_exp_avg_sq where AMSGrad keeps
// one) under `name`; a parameter not yet stepped has none.
void WriteAdamMoments(torch::serialize::OutputArchive& archive, const std::string& name,
                      const torch::optim::Adam& optimizer);

// Replaces `optimizer`'s moments with those WriteAdamMoments wrote under `name`, or, where the
// archive has none, LibTorch's own save under `old_name` (earlier builds' checkpoints), matched
// to the parameters by their place. The optimiser must hold the parameters the moments were
// written for, in the same order. Throws cmbrl::Error naming `file` when neither is there, or
// when moments are missing or of another shape than their parameter.
void ReadAdamMoments(torch::serialize::InputArchive& archive, const std::string& name,
                     const std::string& old_name, torch::optim::Adam& optimizer,
                     const std::string& file);

}  // namespace cmbrl

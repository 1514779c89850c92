#include "cmbrl/models/action_echo_dynamics.h"

#include <torch/torch.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

ActionEchoDynamics::ActionEchoDynamics(const DynamicsModel& model, int offset)
    : model_(model), offset_(offset) {
  Require(offset >= 0 && offset + model.action_dim() <= model.state_dim(),
          "the previous action at state components {} to {} does not fit a state of {}",
          offset, offset + model.action_dim() - 1, model.state_dim());
}

torch::Tensor ActionEchoDynamics::Echo(torch::Tensor next, const torch::Tensor& actions) const {
  next.narrow(-1, offset_, model_.action_dim()).copy_(actions);
  return next;
}

torch::Tensor ActionEchoDynamics::Predict(const torch::Tensor& states,
                                          const torch::Tensor& actions) const {
  return Echo(model_.Predict(states, actions), actions);
}

torch::Tensor ActionEchoDynamics::PredictUnchecked(const torch::Tensor& states,
                                                   const torch::Tensor& actions) const {
  return Echo(model_.PredictUnchecked(states, actions), actions);
}

}  // namespace cmbrl

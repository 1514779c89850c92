#include "cmbrl/policy_opt/adam_archive.h"

#include <cstdint>
#include <memory>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

// The key of a parameter's state in an optimiser's state() map: the address of its tensor, as
// text in LibTorch 1.x and as the pointer itself in 2.x (the CUDA builds' LibTorch).
using StateMapKey = std::decay_t<decltype(std::declval<torch::optim::Adam&>().state())>::key_type;

template <typename Key>
Key StateKeyAs(void* address) {
  if constexpr (std::is_pointer_v<Key>) {
    return address;
  } else {
    std::ostringstream text;  // LibTorch 1.x's own form (c10::guts::to_string)
    text << address;
    return text.str();
  }
}

StateMapKey StateKey(const torch::Tensor& parameter) {
  return StateKeyAs<StateMapKey>(parameter.unsafeGetTensorImpl());
}

}  // namespace

void WriteAdamMoments(torch::serialize::OutputArchive& archive, const std::string& name,
                      const torch::optim::Adam& optimizer) {
  torch::serialize::OutputArchive moments;
  const std::vector<torch::Tensor>& params = optimizer.param_groups().at(0).params();
  for (size_t i = 0; i < params.size(); ++i) {
    const auto found = optimizer.state().find(StateKey(params[i]));
    if (found == optimizer.state().end()) continue;  // not yet stepped
    const auto& state = static_cast<const torch::optim::AdamParamState&>(*found->second);
    const std::string key = std::to_string(i);
    moments.write(key + ".step", torch::tensor(state.step(), torch::kInt64));
    moments.write(key + ".exp_avg", state.exp_avg());
    moments.write(key + ".exp_avg_sq", state.exp_avg_sq());
    if (state.max_exp_avg_sq().defined()) {
      moments.write(key + ".max_exp_avg_sq", state.max_exp_avg_sq());
    }
  }
  archive.write(name, moments);
}

void ReadAdamMoments(torch::serialize::InputArchive& archive, const std::string& name,
                     const std::string& old_name, torch::optim::Adam& optimizer,
                     const std::string& file) {
  torch::serialize::InputArchive moments;
  if (!archive.try_read(name, moments)) {
    Require(archive.try_read(old_name, moments), "'{}' holds no optimiser state for {}", file,
            name);
    optimizer.load(moments);
    return;
  }
  const std::vector<torch::Tensor>& params = optimizer.param_groups().at(0).params();
  optimizer.state().clear();
  for (size_t i = 0; i < params.size(); ++i) {
    const std::string key = std::to_string(i);
    torch::Tensor step;
    if (!moments.try_read(key + ".step", step)) continue;  // not yet stepped when saved
    auto state = std::make_unique<torch::optim::AdamParamState>();
    torch::Tensor exp_avg, exp_avg_sq, max_exp_avg_sq;
    Require(moments.try_read(key + ".exp_avg", exp_avg) &&
                moments.try_read(key + ".exp_avg_sq", exp_avg_sq) &&
                exp_avg.sizes() == params[i].sizes() && exp_avg_sq.sizes() == params[i].sizes(),
            "'{}' is damaged: {}'s moments of parameter {} are missing or of another shape", file,
            name, i);
    state->step(step.item<std::int64_t>());
    state->exp_avg(exp_avg);
    state->exp_avg_sq(exp_avg_sq);
    if (moments.try_read(key + ".max_exp_avg_sq", max_exp_avg_sq)) {
      state->max_exp_avg_sq(max_exp_avg_sq);
    }
    optimizer.state()[StateKey(params[i])] = std::move(state);
  }
}

}  // namespace cmbrl

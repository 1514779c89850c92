#include "cmbrl/models/fused_adam.h"

#include <cmath>

#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"

namespace cmbrl {
namespace {

// The update's constants for one step.
struct AdamStep {
  float beta1, beta2, epsilon;
  float step_size;         // learning_rate / (1 - beta1^t)
  float bias_correction2;  // sqrt(1 - beta2^t)
};

// The constants of step t (counted from 1).
AdamStep StepConstants(const FusedAdamOptions& options, std::int64_t t) {
  const auto steps = static_cast<double>(t);
  const double correction1 = 1.0 - std::pow(options.beta1, steps);
  const double correction2 = 1.0 - std::pow(options.beta2, steps);
  return {static_cast<float>(options.beta1), static_cast<float>(options.beta2),
          static_cast<float>(options.epsilon),
          static_cast<float>(options.learning_rate / correction1),
          static_cast<float>(std::sqrt(correction2))};
}

// One pass over [begin, end) of a parameter: the same arithmetic as PyTorch's Adam.
void UpdateRange(const AdamStep& a, float* param, const float* grad, float* m, float* v,
                 std::int64_t begin, std::int64_t end) {
  for (std::int64_t i = begin; i < end; ++i) {
    const float g = grad[i];
    m[i] = a.beta1 * m[i] + (1.0f - a.beta1) * g;
    v[i] = a.beta2 * v[i] + (1.0f - a.beta2) * g * g;
    param[i] -= a.step_size * m[i] / (std::sqrt(v[i]) / a.bias_correction2 + a.epsilon);
  }
}

}  // namespace

int FusedAdamWorkers(std::int64_t elements) { return elements >= (1 << 18) ? CoreCount() : 1; }

FusedAdam::FusedAdam(std::vector<torch::Tensor> parameters, FusedAdamOptions options)
    : parameters_(std::move(parameters)), options_(options) {
  for (const torch::Tensor& p : parameters_) {
    Require(p.scalar_type() == torch::kFloat && p.is_contiguous(),
            "FusedAdam needs contiguous float32 parameters, got {} of shape {}",
            c10::toString(p.scalar_type()), c10::str(p.sizes()));
    exp_avg_.push_back(torch::zeros_like(p));
    exp_avg_sq_.push_back(torch::zeros_like(p));
  }
}

void FusedAdam::Step() {
  Require(!in_step_, "FusedAdam: Step() inside a step made in parts (EndStep() not called)");
  const torch::NoGradGuard no_grad;
  ++steps_;
  const AdamStep a = StepConstants(options_, steps_);
  for (size_t i = 0; i < parameters_.size(); ++i) {
    torch::Tensor& p = parameters_[i];
    torch::Tensor grad = p.mutable_grad();
    if (!grad.defined()) continue;
    p.mutable_grad() = torch::Tensor();  // the next backward writes a fresh gradient
    torch::Tensor& m = exp_avg_[i];
    torch::Tensor& v = exp_avg_sq_[i];
    if (!p.is_cpu()) {
      // On a GPU the same formula as tensor operations.
      m.mul_(a.beta1).add_(grad, 1.0 - a.beta1);
      v.mul_(a.beta2).addcmul_(grad, grad, 1.0 - a.beta2);
      p.addcdiv_(m, v.sqrt().div_(a.bias_correction2).add_(a.epsilon), -a.step_size);
      continue;
    }
    grad = grad.contiguous();
    float* param = p.data_ptr<float>();
    const float* g = grad.data_ptr<float>();
    float* m_data = m.data_ptr<float>();
    float* v_data = v.data_ptr<float>();
    const std::int64_t n = p.numel();
    ParallelRanges(n, FusedAdamWorkers(n), [&](std::int64_t begin, std::int64_t end) {
      UpdateRange(a, param, g, m_data, v_data, begin, end);
    });
  }
}

void FusedAdam::BeginStep() {
  Require(!in_step_, "FusedAdam: BeginStep() twice without EndStep()");
  in_step_ = true;
  ++steps_;
}

void FusedAdam::StepPart(std::int64_t part, std::int64_t parts) {
  Require(in_step_, "FusedAdam: StepPart() outside BeginStep() and EndStep()");
  Require(parts >= 1 && part >= 0 && part < parts, "FusedAdam: part {} of {}", part, parts);
  const AdamStep a = StepConstants(options_, steps_);
  for (size_t i = 0; i < parameters_.size(); ++i) {
    const torch::Tensor& p = parameters_[i];
    const torch::Tensor grad = p.grad();  // a copy of the handle: safe from several threads
    if (!grad.defined()) continue;
    Require(p.is_cpu() && grad.is_contiguous() && p.dim() >= 1 && p.size(0) % parts == 0,
            "FusedAdam: a step in {} parts needs contiguous CPU gradients and a first dimension "
            "that {} divides; parameter {} has shape {} on {}",
            parts, parts, i, c10::str(p.sizes()), p.device().str());
    const std::int64_t n = p.numel();
    UpdateRange(a, p.data_ptr<float>(), grad.data_ptr<float>(), exp_avg_[i].data_ptr<float>(),
                exp_avg_sq_[i].data_ptr<float>(), n / parts * part, n / parts * (part + 1));
  }
}

void FusedAdam::EndStep() {
  Require(in_step_, "FusedAdam: EndStep() without BeginStep()");
  in_step_ = false;
  for (torch::Tensor& p : parameters_) p.mutable_grad() = torch::Tensor();
}

void FusedAdam::Save(torch::serialize::OutputArchive& archive) const {
  archive.write("steps", torch::tensor({steps_}, torch::kLong));
  for (size_t i = 0; i < parameters_.size(); ++i) {
    archive.write("exp_avg" + std::to_string(i), exp_avg_[i].cpu());
    archive.write("exp_avg_sq" + std::to_string(i), exp_avg_sq_[i].cpu());
  }
}

void FusedAdam::Load(torch::serialize::InputArchive& archive, const std::string& source) {
  const auto read = [&](const std::string& key, const torch::Tensor& like) {
    torch::Tensor t;
    Require(archive.try_read(key, t),
            "'{}' has no Adam state '{}': it was written by an older cmbrl whose optimiser state "
            "this version cannot read; start a new run",
            source, key);
    Require(t.sizes() == like.sizes(), "Adam state '{}' in '{}' has shape {}, expected {}", key,
            source, c10::str(t.sizes()), c10::str(like.sizes()));
    return t;
  };
  const torch::NoGradGuard no_grad;
  steps_ = read("steps", torch::empty({1})).item<std::int64_t>();
  for (size_t i = 0; i < parameters_.size(); ++i) {
    exp_avg_[i].copy_(read("exp_avg" + std::to_string(i), exp_avg_[i]));
    exp_avg_sq_[i].copy_(read("exp_avg_sq" + std::to_string(i), exp_avg_sq_[i]));
  }
}

}  // namespace cmbrl

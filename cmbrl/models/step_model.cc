#include "cmbrl/models/step_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"

namespace cmbrl {
namespace {

constexpr double kMinStd = 1e-6;  // a normaliser's smaller standard deviations become 1

// Column means and standard deviations of (N, W) rows; tiny deviations become 1.
std::pair<torch::Tensor, torch::Tensor> Moments(const torch::Tensor& rows) {
  const torch::Tensor mean = rows.mean(0);
  torch::Tensor std = rows.std(0, /*unbiased=*/false);
  std = torch::where(std < kMinStd, torch::ones_like(std), std);
  return {mean, std};
}

// A random split of `n` rows into (validation, train) row indices, `fraction` of them held
// out (at least 1, at most n - 1). With `labels` (0/1), each class is split on its own, so that
// a rare class (an episode's one terminal step) is in both parts where it has 2 rows or more.
std::pair<torch::Tensor, torch::Tensor> Split(std::int64_t n, double fraction,
                                              const torch::Tensor* labels,
                                              at::Generator& generator) {
  const auto held_of = [fraction](std::int64_t count) {
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(fraction * count)), 1,
                                    count - 1);
  };
  if (labels == nullptr) {
    const torch::Tensor order = torch::randperm(n, generator);
    const std::int64_t held = held_of(n);
    return {order.slice(0, 0, held), order.slice(0, held)};
  }
  std::vector<torch::Tensor> validation, train;
  for (const bool positive : {false, true}) {
    const torch::Tensor rows = torch::nonzero(positive ? *labels > 0.5 : *labels <= 0.5).view(-1);
    const std::int64_t count = rows.size(0);
    if (count == 0) continue;
    const torch::Tensor order = rows.index_select(0, torch::randperm(count, generator));
    const std::int64_t held = count < 2 ? 0 : held_of(count);
    validation.push_back(order.slice(0, 0, held));
    train.push_back(order.slice(0, held));
  }
  torch::Tensor held = torch::cat(validation), kept = torch::cat(train);
  if (held.size(0) == 0) {  // one row of each class: the validation takes a training row
    held = kept.slice(0, 0, 1);
    kept = kept.slice(0, 1);
  }
  return {held, kept};
}

}  // namespace

const char* StepSignalName(StepSignal signal) {
  return signal == StepSignal::kReward ? "reward" : "termination";
}

StepModel::StepModel(StepSignal signal, int input_dim, StepModelOptions options, std::uint64_t seed)
    : signal_(signal),
      input_dim_(input_dim),
      options_(std::move(options)),
      generator_(MakeCpuGenerator(seed)) {
  Require(input_dim >= 1, "input_dim is {}: expected at least 1", input_dim);
  ValidateStepModelOptions(options_);
  input_mean_ = torch::zeros({input_dim_});
  input_std_ = torch::ones({input_dim_});
  target_mean_ = torch::zeros({1});
  target_std_ = torch::ones({1});
  InitialiseWeights();
}

StepModel::~StepModel() = default;

void StepModel::InitialiseWeights() {
  // PyTorch's Linear default: uniform in +-1/sqrt(fan_in), drawn from the model's generator.
  weights_.clear();
  biases_.clear();
  int in = input_dim_;
  std::vector<int> widths = options_.hidden_sizes;
  widths.push_back(1);
  for (const int out : widths) {
    const double bound = 1.0 / std::sqrt(static_cast<double>(in));
    weights_.push_back((torch::rand({in, out}, generator_) * 2 - 1) * bound);
    biases_.push_back((torch::rand({out}, generator_) * 2 - 1) * bound);
    in = out;
  }
}

torch::Tensor StepModel::Forward(const torch::Tensor& normalized) const {
  torch::Tensor h = normalized;
  for (size_t l = 0; l < weights_.size(); ++l) {
    h = torch::addmm(biases_[l], h, weights_[l]);
    if (l + 1 < weights_.size()) h = torch::relu(h);
  }
  return h.squeeze(-1);
}

torch::Tensor StepModel::Loss(const torch::Tensor& outputs, const torch::Tensor& targets) const {
  if (signal_ == StepSignal::kReward) return (outputs - targets).pow(2).mean();
  return torch::binary_cross_entropy_with_logits(outputs, targets);
}

StepFitReport StepModel::Fit(const torch::Tensor& inputs, const torch::Tensor& targets) {
  const auto start = std::chrono::steady_clock::now();
  const char* name = StepSignalName(signal_);
  Require(inputs.dim() == 2 && inputs.size(1) == input_dim_ && targets.dim() == 1 &&
              targets.size(0) == inputs.size(0),
          "the {0} model fits (N, {1}) inputs to (N) {0}s: got {2} and {3}", name, input_dim_,
          c10::str(inputs.sizes()), c10::str(targets.sizes()));
  const std::int64_t n = inputs.size(0);
  Require(n >= 2, "the {} model needs at least 2 steps to fit, got {}", name, n);
  CheckFinite(inputs, signal_ == StepSignal::kReward ? "the reward model's inputs"
                                                     : "the termination model's inputs");
  CheckFinite(targets, signal_ == StepSignal::kReward ? "the rewards" : "the terminations");
  const torch::Tensor x_all = inputs.to(torch::kCPU, torch::kFloat);
  const torch::Tensor y_all = targets.to(torch::kCPU, torch::kFloat);
  const bool binary = signal_ == StepSignal::kTermination;
  if (binary) {
    Require((y_all == 0).logical_or(y_all == 1).all().item<bool>(),
            "the terminations to fit are not all 0 or 1");
  }

  // A fresh split and fresh weights at every fit.
  const auto [validation, train] =
      Split(n, options_.validation_fraction, binary ? &y_all : nullptr, generator_);
  std::tie(input_mean_, input_std_) = Moments(x_all.index_select(0, train));
  if (!binary) {
    std::tie(target_mean_, target_std_) = Moments(y_all.index_select(0, train).unsqueeze(1));
  }
  const torch::Tensor x = (x_all - input_mean_) / input_std_;
  const torch::Tensor y = ((y_all - target_mean_) / target_std_).squeeze(-1);
  InitialiseWeights();

  std::vector<torch::Tensor> parameters;
  for (size_t l = 0; l < weights_.size(); ++l) {
    parameters.push_back(weights_[l].requires_grad_(true));
    parameters.push_back(biases_[l].requires_grad_(true));
  }
  torch::optim::Adam optimiser(parameters, torch::optim::AdamOptions(options_.learning_rate));
  const torch::Tensor x_val = x.index_select(0, validation), y_val = y.index_select(0, validation);
  // The losses in the signal's units: a standardised reward's squared error times its variance.
  const double scale = binary ? 1.0 : target_std_.item<double>() * target_std_.item<double>();
  StepFitReport report;
  report.train_size = static_cast<int>(train.size(0));
  report.validation_size = static_cast<int>(validation.size(0));
  double best = std::numeric_limits<double>::infinity();
  std::vector<torch::Tensor> best_weights, best_biases;
  int since_best = 0;
  for (int epoch = 0; epoch < options_.max_epochs && since_best < options_.patience; ++epoch) {
    report.train_loss = TrainEpoch(optimiser, x, y, train) * scale;
    ++report.epochs;
    torch::NoGradGuard no_grad;
    const double validation_loss = Loss(Forward(x_val), y_val).item<double>() * scale;
    if (validation_loss < best) {
      best = validation_loss;
      since_best = 0;
      best_weights.clear();
      best_biases.clear();
      for (size_t l = 0; l < weights_.size(); ++l) {
        best_weights.push_back(weights_[l].detach().clone());
        best_biases.push_back(biases_[l].detach().clone());
      }
    } else {
      ++since_best;
    }
  }
  weights_ = std::move(best_weights);
  biases_ = std::move(best_biases);
  report.validation_loss = best;
  fitted_ = true;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

double StepModel::TrainEpoch(torch::optim::Optimizer& optimiser, const torch::Tensor& x,
                             const torch::Tensor& y, const torch::Tensor& train) {
  const torch::Tensor shuffled = train.index_select(0, torch::randperm(train.size(0), generator_));
  double sum = 0.0;
  for (std::int64_t begin = 0; begin < shuffled.size(0); begin += options_.batch_size) {
    const torch::Tensor rows = shuffled.slice(0, begin, begin + options_.batch_size);
    optimiser.zero_grad();
    const torch::Tensor loss = Loss(Forward(x.index_select(0, rows)), y.index_select(0, rows));
    loss.backward();
    optimiser.step();
    sum += loss.item<double>() * static_cast<double>(rows.size(0));
  }
  return sum / static_cast<double>(shuffled.size(0));
}

torch::Tensor StepModel::Predict(const torch::Tensor& inputs) const {
  if (inputs.size(-1) != input_dim_) {
    Fail("the {} model reads {} values per step, got {}", StepSignalName(signal_), input_dim_,
         inputs.size(-1));
  }
  std::vector<std::int64_t> leading(inputs.sizes().begin(), inputs.sizes().end() - 1);
  if (!fitted_) return torch::zeros(leading, inputs.options().dtype(torch::kFloat));
  torch::NoGradGuard no_grad;
  const torch::Tensor rows = inputs.reshape({-1, input_dim_}).to(torch::kCPU, torch::kFloat);
  const torch::Tensor outputs = Forward((rows - input_mean_) / input_std_);
  const torch::Tensor values = signal_ == StepSignal::kReward ? outputs * target_std_ + target_mean_
                                                              : torch::sigmoid(outputs);
  return values.view(leading).to(inputs.device());
}

void StepModel::Save(const std::string& path) const {
  torch::serialize::OutputArchive archive;
  archive.write("signal", torch::tensor(static_cast<std::int64_t>(signal_)));
  archive.write("input_dim", torch::tensor(static_cast<std::int64_t>(input_dim_)));
  archive.write("layers", torch::tensor(static_cast<std::int64_t>(weights_.size())));
  for (size_t l = 0; l < weights_.size(); ++l) {
    archive.write("weight" + std::to_string(l), weights_[l].detach());
    archive.write("bias" + std::to_string(l), biases_[l].detach());
  }
  archive.write("input_mean", input_mean_);
  archive.write("input_std", input_std_);
  archive.write("target_mean", target_mean_);
  archive.write("target_std", target_std_);
  archive.write("fitted", torch::tensor(static_cast<std::int64_t>(fitted_)));
  archive.write("generator", generator_.get_state());
  SaveArchive(archive, path);
}

void StepModel::Load(const std::string& path) {
  torch::serialize::InputArchive archive;
  const auto read = [&](const std::string& key) {
    torch::Tensor t;
    archive.read(key, t);
    return t;
  };
  try {
    archive.load_from(path);
    // A file without "signal" and with "reward_mean" predates the termination model: a reward's.
    torch::Tensor signal;
    const bool older = !archive.try_read("signal", signal);
    const StepSignal stored =
        older ? StepSignal::kReward : static_cast<StepSignal>(signal.item<std::int64_t>());
    Require(stored == signal_, "'{}' holds a {} model, not a {} model", path,
            StepSignalName(stored), StepSignalName(signal_));
    const std::int64_t input_dim = read("input_dim").item<std::int64_t>();
    const std::int64_t layers = read("layers").item<std::int64_t>();
    Require(input_dim == input_dim_ && layers == static_cast<std::int64_t>(weights_.size()),
            "'{}' holds a {} model of {} inputs and {} layers; this one has {} and {}", path,
            StepSignalName(signal_), input_dim, layers, input_dim_, weights_.size());
    std::vector<torch::Tensor> weights, biases;
    for (std::int64_t l = 0; l < layers; ++l) {
      weights.push_back(read("weight" + std::to_string(l)));
      biases.push_back(read("bias" + std::to_string(l)));
      Require(weights.back().sizes() == weights_[l].sizes() &&
                  biases.back().sizes() == biases_[l].sizes(),
              "'{}' layer {} is {}: this model's is {} (other hidden_sizes)", path, l,
              c10::str(weights.back().sizes()), c10::str(weights_[l].sizes()));
    }
    input_mean_ = read("input_mean");
    input_std_ = read("input_std");
    target_mean_ = read(older ? "reward_mean" : "target_mean");
    target_std_ = read(older ? "reward_std" : "target_std");
    fitted_ = read("fitted").item<std::int64_t>() != 0;
    generator_.set_state(read("generator"));
    weights_ = std::move(weights);
    biases_ = std::move(biases);
  } catch (const c10::Error&) {
    Fail("'{}' is damaged: not a {} model LibTorch can read", path, StepSignalName(signal_));
  }
}

torch::Tensor StepInputs(const TransitionBuffer& buffer) {
  const std::int64_t n = buffer.size();
  const auto rows = [n](const float* data, int width) {
    return torch::from_blob(const_cast<float*>(data), {n, width}, torch::kFloat);
  };
  return torch::cat(
      {rows(buffer.states(), buffer.state_dim()), rows(buffer.actions(), buffer.action_dim()),
       rows(buffer.next_states(), buffer.state_dim())},
      1);
}

torch::Tensor StoredRewards(const TransitionBuffer& buffer) {
  Require(buffer.keeps_rewards(), "this transition buffer keeps no rewards");
  return torch::from_blob(const_cast<float*>(buffer.rewards()), {buffer.size()}, torch::kFloat)
      .clone();
}

torch::Tensor StoredTerminations(const TransitionBuffer& buffer) {
  Require(buffer.keeps_terminations(), "this transition buffer keeps no terminations");
  return torch::from_blob(const_cast<float*>(buffer.terminations()), {buffer.size()}, torch::kFloat)
      .clone();
}

torch::Tensor StepInputs(const torch::Tensor& states, const torch::Tensor& actions,
                         const torch::Tensor& next_states) {
  return torch::cat({states, actions, next_states}, -1);
}

}  // namespace cmbrl

#include "cmbrl/models/reward_model.h"

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

}  // namespace

RewardModel::RewardModel(int input_dim, RewardModelOptions options, std::uint64_t seed)
    : input_dim_(input_dim), options_(std::move(options)), generator_(MakeCpuGenerator(seed)) {
  Require(input_dim >= 1, "input_dim is {}: expected at least 1", input_dim);
  ValidateRewardModelOptions(options_);
  input_mean_ = torch::zeros({input_dim_});
  input_std_ = torch::ones({input_dim_});
  reward_mean_ = torch::zeros({1});
  reward_std_ = torch::ones({1});
  InitialiseWeights();
}

RewardModel::~RewardModel() = default;

void RewardModel::InitialiseWeights() {
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

torch::Tensor RewardModel::Forward(const torch::Tensor& normalized) const {
  torch::Tensor h = normalized;
  for (size_t l = 0; l < weights_.size(); ++l) {
    h = torch::addmm(biases_[l], h, weights_[l]);
    if (l + 1 < weights_.size()) h = torch::relu(h);
  }
  return h.squeeze(-1);
}

RewardFitReport RewardModel::Fit(const torch::Tensor& inputs, const torch::Tensor& rewards) {
  const auto start = std::chrono::steady_clock::now();
  Require(inputs.dim() == 2 && inputs.size(1) == input_dim_ && rewards.dim() == 1 &&
              rewards.size(0) == inputs.size(0),
          "the reward model fits (N, {}) inputs to (N) rewards: got {} and {}", input_dim_,
          c10::str(inputs.sizes()), c10::str(rewards.sizes()));
  const std::int64_t n = inputs.size(0);
  Require(n >= 2, "the reward model needs at least 2 steps to fit, got {}", n);
  CheckFinite(inputs, "the reward model's inputs");
  CheckFinite(rewards, "the rewards");
  const torch::Tensor x_all = inputs.to(torch::kCPU, torch::kFloat);
  const torch::Tensor y_all = rewards.to(torch::kCPU, torch::kFloat);

  // A fresh split and fresh weights at every fit.
  const std::int64_t held = std::clamp<std::int64_t>(
      static_cast<std::int64_t>(std::ceil(options_.validation_fraction * n)), 1, n - 1);
  const torch::Tensor order = torch::randperm(n, generator_);
  const torch::Tensor validation = order.slice(0, 0, held), train = order.slice(0, held);
  std::tie(input_mean_, input_std_) = Moments(x_all.index_select(0, train));
  std::tie(reward_mean_, reward_std_) = Moments(y_all.index_select(0, train).unsqueeze(1));
  const torch::Tensor x = (x_all - input_mean_) / input_std_;
  const torch::Tensor y = ((y_all - reward_mean_) / reward_std_).squeeze(-1);
  InitialiseWeights();

  std::vector<torch::Tensor> parameters;
  for (size_t l = 0; l < weights_.size(); ++l) {
    parameters.push_back(weights_[l].requires_grad_(true));
    parameters.push_back(biases_[l].requires_grad_(true));
  }
  torch::optim::Adam optimiser(parameters, torch::optim::AdamOptions(options_.learning_rate));
  const torch::Tensor x_val = x.index_select(0, validation), y_val = y.index_select(0, validation);
  const double scale = reward_std_.item<double>() * reward_std_.item<double>();
  RewardFitReport report;
  report.train_size = static_cast<int>(n - held);
  report.validation_size = static_cast<int>(held);
  double best = std::numeric_limits<double>::infinity();
  std::vector<torch::Tensor> best_weights, best_biases;
  int since_best = 0;
  for (int epoch = 0; epoch < options_.max_epochs && since_best < options_.patience; ++epoch) {
    report.train_mse = TrainEpoch(optimiser, x, y, train) * scale;
    ++report.epochs;
    torch::NoGradGuard no_grad;
    const double validation_mse = (Forward(x_val) - y_val).pow(2).mean().item<double>() * scale;
    if (validation_mse < best) {
      best = validation_mse;
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
  report.validation_mse = best;
  fitted_ = true;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

double RewardModel::TrainEpoch(torch::optim::Optimizer& optimiser, const torch::Tensor& x,
                               const torch::Tensor& y, const torch::Tensor& train) {
  const torch::Tensor shuffled = train.index_select(0, torch::randperm(train.size(0), generator_));
  double sum = 0.0;
  for (std::int64_t begin = 0; begin < shuffled.size(0); begin += options_.batch_size) {
    const torch::Tensor rows = shuffled.slice(0, begin, begin + options_.batch_size);
    optimiser.zero_grad();
    const torch::Tensor loss =
        (Forward(x.index_select(0, rows)) - y.index_select(0, rows)).pow(2).mean();
    loss.backward();
    optimiser.step();
    sum += loss.item<double>() * static_cast<double>(rows.size(0));
  }
  return sum / static_cast<double>(shuffled.size(0));
}

torch::Tensor RewardModel::Predict(const torch::Tensor& inputs) const {
  Require(inputs.size(-1) == input_dim_, "the reward model reads {} values per step, got {}",
          input_dim_, inputs.size(-1));
  std::vector<std::int64_t> leading(inputs.sizes().begin(), inputs.sizes().end() - 1);
  if (!fitted_) return torch::zeros(leading, inputs.options().dtype(torch::kFloat));
  torch::NoGradGuard no_grad;
  const torch::Tensor rows = inputs.reshape({-1, input_dim_}).to(torch::kCPU, torch::kFloat);
  const torch::Tensor rewards =
      Forward((rows - input_mean_) / input_std_) * reward_std_ + reward_mean_;
  return rewards.view(leading).to(inputs.device());
}

void RewardModel::Save(const std::string& path) const {
  torch::serialize::OutputArchive archive;
  archive.write("input_dim", torch::tensor(static_cast<std::int64_t>(input_dim_)));
  archive.write("layers", torch::tensor(static_cast<std::int64_t>(weights_.size())));
  for (size_t l = 0; l < weights_.size(); ++l) {
    archive.write("weight" + std::to_string(l), weights_[l].detach());
    archive.write("bias" + std::to_string(l), biases_[l].detach());
  }
  archive.write("input_mean", input_mean_);
  archive.write("input_std", input_std_);
  archive.write("reward_mean", reward_mean_);
  archive.write("reward_std", reward_std_);
  archive.write("fitted", torch::tensor(static_cast<std::int64_t>(fitted_)));
  archive.write("generator", generator_.get_state());
  SaveArchive(archive, path);
}

void RewardModel::Load(const std::string& path) {
  torch::serialize::InputArchive archive;
  const auto read = [&](const std::string& key) {
    torch::Tensor t;
    archive.read(key, t);
    return t;
  };
  try {
    archive.load_from(path);
    const std::int64_t input_dim = read("input_dim").item<std::int64_t>();
    const std::int64_t layers = read("layers").item<std::int64_t>();
    Require(input_dim == input_dim_ && layers == static_cast<std::int64_t>(weights_.size()),
            "'{}' holds a reward model of {} inputs and {} layers; this one has {} and {}", path,
            input_dim, layers, input_dim_, weights_.size());
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
    reward_mean_ = read("reward_mean");
    reward_std_ = read("reward_std");
    fitted_ = read("fitted").item<std::int64_t>() != 0;
    generator_.set_state(read("generator"));
    weights_ = std::move(weights);
    biases_ = std::move(biases);
  } catch (const c10::Error&) {
    Fail("'{}' is damaged: not a reward model LibTorch can read", path);
  }
}

torch::Tensor RewardInputs(const TransitionBuffer& buffer) {
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

torch::Tensor RewardInputs(const torch::Tensor& states, const torch::Tensor& actions,
                           const torch::Tensor& next_states) {
  return torch::cat({states, actions, next_states}, -1);
}

}  // namespace cmbrl

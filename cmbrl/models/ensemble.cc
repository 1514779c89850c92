#include "cmbrl/models/ensemble.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "cmbrl/core/check.h"
#include "cmbrl/core/cpu_features.h"
#include "cmbrl/core/memory.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/models/fused_adam.h"
#include "cmbrl/models/normalizer.h"
#include "cmbrl/models/onednn_forward.h"
#include "cmbrl/models/onednn_training.h"

namespace cmbrl {

struct EnsembleDynamics::State {
  torch::Device device{torch::kCPU};
  std::vector<torch::Tensor> weights;  // layer l: (E, in_l, out_l)
  std::vector<torch::Tensor> biases;   // layer l: (E, 1, out_l)
  // With precision bf16: bfloat16 copies of weights and biases for predictions.
  std::vector<torch::Tensor> predict_weights;
  std::vector<torch::Tensor> predict_biases;
  std::unique_ptr<OnednnEnsembleForward> onednn;  // with backend onednn: the predictions
  std::unique_ptr<OnednnEnsembleTraining> onednn_training;  // and the training products
  Normalizer input_normalizer;         // over [state, action]
  Normalizer target_normalizer;        // over next state (or its change)
  std::unique_ptr<FusedAdam> optimizer;
  at::Generator generator;
  int fits = 0;
  // A fit paused part-way (Fit's pause_due): where it stands, and the generator's state when it
  // began, which gives its train/validation split again.
  struct OpenFit {
    std::int64_t rows = 0;  // of the data it fits
    int next_epoch = 1;
    double validation_mse = 0.0;
    double best_validation_mse = 0.0;
    int checks_without_improvement = 0;
    torch::Tensor split_generator;
  };
  std::optional<OpenFit> open_fit;

  // The buffer's inputs [state, action] (n, S + A) and targets (n, S), the next state or its
  // change, normalised on the device by normalisers fitted to them (anew at every fit, over the
  // whole buffer).
  std::pair<torch::Tensor, torch::Tensor> NormalizedFitData(const TransitionBuffer& data,
                                                            const EnsembleOptions& options) {
    const std::int64_t n = data.size();
    const auto rows = [n](const float* values, std::int64_t dim) {
      return torch::from_blob(const_cast<float*>(values), {n, dim}, torch::kFloat).clone();
    };
    const torch::Tensor states = rows(data.states(), data.state_dim());
    const torch::Tensor inputs = torch::cat({states, rows(data.actions(), data.action_dim())}, 1);
    torch::Tensor targets = rows(data.next_states(), data.state_dim());
    if (options.predict_delta) targets = targets - states;
    input_normalizer.Fit(inputs, options.min_std);
    target_normalizer.Fit(targets, options.min_std);
    return {input_normalizer.Normalize(inputs.to(device)),
            target_normalizer.Normalize(targets.to(device))};
  }

  // A fit's rows of n transitions, shuffled: the first validation_size validate, the rest train.
  struct Split {
    OpenFit place;               // where the fit stands (an open one's, or a new one's first epoch)
    torch::Tensor validation_rows;  // (V) on the device
    torch::Tensor train_rows;       // (n - V) on the device
  };

  // A fresh train/validation split, or an open fit's own again (drawn from the generator's state
  // when it began). Takes the open fit, if any: the fit now runs it.
  Split TakeSplit(std::int64_t n, std::int64_t validation_size) {
    Split split;
    torch::Tensor order;
    if (open_fit) {
      split.place = std::move(*open_fit);
      open_fit.reset();
      Require(split.place.rows == n,
              "the open dynamics fit was begun on {} transitions, but is given {}: an open fit "
              "goes on only on its own data",
              split.place.rows, n);
      const torch::Tensor now = generator.get_state();
      generator.set_state(split.place.split_generator);
      order = torch::randperm(n, generator, torch::kLong);
      generator.set_state(now);
    } else {
      split.place.rows = n;
      split.place.split_generator = generator.get_state();
      order = torch::randperm(n, generator, torch::kLong);
    }
    split.validation_rows = order.slice(0, 0, validation_size).to(device);
    split.train_rows = order.slice(0, validation_size).to(device);
    return split;
  }
};

namespace {

std::string ResolveBackend(const EnsembleOptions& o) {
  if (o.backend != "auto") return o.backend;
  // oneDNN wherever it runs: measured faster than LibTorch's path on every CPU tried, 1.2-1.6x a
  // planning step on an AVX2 core (docs/PERFORMANCE.md).
  return o.device == "cpu" && o.precision != "tf32" && OnednnForwardAvailable(o.precision == "bf16")
             ? "onednn"
             : "libtorch";
}

// Whether the training products go through oneDNN, given the prediction backend: always with
// backend onednn; with auto at any width on a CPU with AVX-512, and elsewhere only for layers at
// most 256 wide. Measured (docs/PERFORMANCE.md): on an AVX2 core (v0.7) oneDNN's epoch was
// 1.14-1.24x LibTorch's at widths 200 and 256, 0.88x at 512 and 0.81x at 1024 (its products on
// unreordered weights fall behind OpenBLAS); on AVX-512 cores 1.15-1.38x up to 512 (v0.8), and
// at 1024 the paper's epoch (50,000 transitions) 1.09x on an Emerald Rapids and 1.16x on a Zen 4
// (v0.9). A fixed rule of the config and the CPU's vector ISA, not a timing, so that a config
// gives the same bits on one machine.
int AutoOnednnTrainingWidth() { return CpuHasAvx512() ? std::numeric_limits<int>::max() : 256; }

bool TrainsThroughOnednn(const EnsembleOptions& o, const std::string& backend) {
  if (backend != "onednn") return false;
  if (o.backend == "onednn") return true;
  return *std::max_element(o.hidden_sizes.begin(), o.hidden_sizes.end()) <=
         AutoOnednnTrainingWidth();
}

}  // namespace

EnsembleDynamics::EnsembleDynamics(int state_dim, int action_dim, EnsembleOptions options,
                                   std::uint64_t seed)
    : state_dim_(state_dim),
      action_dim_(action_dim),
      options_(std::move(options)),
      state_(std::make_unique<State>()) {
  Require(state_dim >= 1, "state_dim is {}: expected a positive number", state_dim);
  Require(action_dim >= 1, "action_dim is {}: expected a positive number", action_dim);
  ValidateEnsembleOptions(options_);
  RequireMemory(EnsembleParameterBytes(options_, state_dim, action_dim),
                fmt::format("an ensemble of {} members with hidden layers [{}] (weights, "
                            "gradients and Adam's moments)",
                            options_.ensemble_size, fmt::join(options_.hidden_sizes, ", ")),
                "use narrower or fewer hidden layers (hidden_sizes) or fewer members");
  // Whether oneDNN runs here is this machine's matter, not the options': checked on building.
  if (options_.backend == "onednn") {
    std::string why_not;
    Require(OnednnForwardAvailable(options_.precision == "bf16", &why_not),
            "backend is onednn but {}; use auto or libtorch", why_not);
  }
  backend_ = ResolveBackend(options_);
  State& s = *state_;
  s.device = ParseDevice(options_.device);
  s.generator = MakeCpuGenerator(seed);
  s.input_normalizer = Normalizer(state_dim + action_dim);
  s.target_normalizer = Normalizer(state_dim);
  s.input_normalizer.To(s.device);
  s.target_normalizer.To(s.device);

  // Weights N(0, init_std) (facts B3); biases as PyTorch's Linear: U(-1/sqrt(in), 1/sqrt(in)).
  // Drawn on the CPU from the seeded generator, then moved: the same on every device.
  std::vector<int> sizes = {state_dim + action_dim};
  sizes.insert(sizes.end(), options_.hidden_sizes.begin(), options_.hidden_sizes.end());
  sizes.push_back(state_dim);
  const std::int64_t members = options_.ensemble_size;
  std::vector<torch::Tensor> parameters;
  for (size_t layer = 0; layer + 1 < sizes.size(); ++layer) {
    const std::int64_t in = sizes[layer], out = sizes[layer + 1];
    const double bound = 1.0 / std::sqrt(static_cast<double>(in));
    torch::Tensor weight =
        torch::empty({members, in, out}).normal_(0.0, options_.init_std, s.generator);
    torch::Tensor bias = torch::empty({members, 1, out}).uniform_(-bound, bound, s.generator);
    s.weights.push_back(weight.to(s.device).requires_grad_(true));
    s.biases.push_back(bias.to(s.device).requires_grad_(true));
    parameters.push_back(s.weights.back());
    parameters.push_back(s.biases.back());
  }
  FusedAdamOptions adam;
  adam.learning_rate = options_.learning_rate;
  s.optimizer = std::make_unique<FusedAdam>(parameters, adam);
  if (options_.precision == "tf32") at::globalContext().setAllowTF32CuBLAS(true);
  if (backend_ == "onednn") {
    s.onednn = std::make_unique<OnednnEnsembleForward>(options_.precision == "bf16");
  }
  if (TrainsThroughOnednn(options_, backend_)) {
    // Training stays float32 whatever the prediction precision.
    s.onednn_training = std::make_unique<OnednnEnsembleTraining>(
        std::vector<std::int64_t>(sizes.begin(), sizes.end()));
  }
  RefreshPredictionWeights();
}

void EnsembleDynamics::RefreshPredictionWeights() {
  State& s = *state_;
  s.predict_weights.clear();
  s.predict_biases.clear();
  if (s.onednn) {
    s.onednn->SetWeights(s.weights, s.biases, s.input_normalizer.mean(),
                         s.input_normalizer.std(), s.target_normalizer.mean(),
                         s.target_normalizer.std(), options_.predict_delta);
    return;
  }
  if (options_.precision != "bf16") return;
  const torch::NoGradGuard no_grad;
  for (size_t l = 0; l < s.weights.size(); ++l) {
    s.predict_weights.push_back(s.weights[l].to(torch::kBFloat16));
    s.predict_biases.push_back(s.biases[l].to(torch::kBFloat16));
  }
}

EnsembleDynamics::~EnsembleDynamics() = default;

std::string EnsembleDynamics::training_backend() const {
  return state_->onednn_training ? "onednn" : "libtorch";
}

torch::Tensor EnsembleDynamics::Forward(const torch::Tensor& x, bool prediction) const {
  const State& s = *state_;
  const bool reduced = prediction && !s.predict_weights.empty();
  const std::vector<torch::Tensor>& weights = reduced ? s.predict_weights : s.weights;
  const std::vector<torch::Tensor>& biases = reduced ? s.predict_biases : s.biases;
  torch::Tensor h = reduced ? x.to(torch::kBFloat16) : x;  // (E, N, in)
  const size_t layers = weights.size();
  for (size_t l = 0; l < layers; ++l) {
    h = torch::baddbmm(biases[l], h, weights[l]);
    // Not relu_(): in place measured 1.7x slower for the planner's small products (LibTorch 1.13).
    if (l + 1 < layers) h = torch::relu(h);
  }
  return reduced ? h.to(torch::kFloat) : h;  // (E, N, S), normalised targets
}

torch::Tensor EnsembleDynamics::PredictUnchecked(const torch::Tensor& states,
                                                 const torch::Tensor& actions) const {
  const torch::NoGradGuard no_grad;
  const State& s = *state_;
  CheckFloatTensor(states, "states", state_dim_, s.device);
  CheckFloatTensor(actions, "actions", action_dim_, s.device);
  Require(states.dim() == 3 && states.size(0) == options_.ensemble_size,
          "states have shape {}: expected (E={}, N, {})", c10::str(states.sizes()),
          options_.ensemble_size, state_dim_);
  Require(
      actions.dim() == 3 && actions.size(0) == states.size(0) && actions.size(1) == states.size(1),
      "actions have shape {}: expected (E={}, N={}, {})", c10::str(actions.sizes()),
      options_.ensemble_size, states.size(1), action_dim_);
  if (s.onednn) return s.onednn->Predict(states, actions);
  const torch::Tensor inputs = s.input_normalizer.Normalize(torch::cat({states, actions}, -1));
  torch::Tensor next = s.target_normalizer.Denormalize(Forward(inputs, /*prediction=*/true));
  if (options_.predict_delta) next = next + states;
  return next;
}

torch::Tensor EnsembleDynamics::Predict(const torch::Tensor& states,
                                        const torch::Tensor& actions) const {
  CheckFloatTensor(states, "states", state_dim_, state_->device);
  CheckFloatTensor(actions, "actions", action_dim_, state_->device);
  CheckFinite(states, "states");
  CheckFinite(actions, "actions");
  return PredictUnchecked(states, actions);
}

bool EnsembleDynamics::fit_open() const { return state_->open_fit.has_value(); }

EnsembleFitReport EnsembleDynamics::Fit(const TransitionBuffer& data,
                                        const std::function<bool()>& keep_going,
                                        const std::function<bool()>& pause_due) {
  const auto start = std::chrono::steady_clock::now();
  Require(data.state_dim() == state_dim_ && data.action_dim() == action_dim_,
          "transition buffer is ({}, {}) but the ensemble is ({}, {}) (state, action)",
          data.state_dim(), data.action_dim(), state_dim_, action_dim_);
  const std::int64_t n = data.size();
  Require(n >= 2, "a dynamics fit needs at least 2 transitions, the buffer has {}", n);
  State& s = *state_;
  const std::int64_t members = options_.ensemble_size;

  const auto [x, y] = s.NormalizedFitData(data, options_);

  // At least one row trains. An open fit draws its own split again.
  const std::int64_t validation_size = std::min(
      static_cast<std::int64_t>(std::floor(options_.validation_fraction * n)), n - 1);
  State::Split split = s.TakeSplit(n, validation_size);
  State::OpenFit& place = split.place;
  const std::int64_t train_size = n - validation_size;
  const std::int64_t subset = std::max<std::int64_t>(
      1, static_cast<std::int64_t>(options_.member_subset_fraction * train_size));
  const torch::Tensor x_val = x.index_select(0, split.validation_rows)
                                  .unsqueeze(0)
                                  .expand({members, validation_size, x.size(1)});
  const torch::Tensor y_val = y.index_select(0, split.validation_rows);

  EnsembleFitReport report;
  report.train_size = static_cast<int>(train_size);
  report.validation_size = static_cast<int>(validation_size);
  const bool continued = place.next_epoch > 1;
  report.validation_mse =
      continued ? place.validation_mse : std::numeric_limits<double>::quiet_NaN();
  report.best_validation_mse =
      continued ? place.best_validation_mse : std::numeric_limits<double>::infinity();
  int checks_without_improvement = place.checks_without_improvement;
  for (int epoch = place.next_epoch; epoch <= options_.max_epochs; ++epoch) {
    report.train_mse = TrainEpoch(x, y, split.train_rows, subset);
    report.epochs = epoch;
    if (keep_going && !keep_going()) {
      report.interrupted = true;
      break;
    }
    if (validation_size > 0 && epoch % options_.validate_every == 0) {
      const torch::NoGradGuard no_grad;
      report.validation_mse =
          (Forward(x_val, false) - y_val.unsqueeze(0)).pow(2).mean().item<double>();
      if (report.validation_mse < report.best_validation_mse) {
        report.best_validation_mse = report.validation_mse;
        checks_without_improvement = 0;
      } else if (++checks_without_improvement >= options_.patience) {
        report.stopped_early = true;
        break;
      }
    }
    // Leaves the fit open after this epoch when pause_due asks (never after its last epoch).
    if (pause_due && epoch < options_.max_epochs && pause_due()) {
      place.next_epoch = epoch + 1;
      place.validation_mse = report.validation_mse;
      place.best_validation_mse = report.best_validation_mse;
      place.checks_without_improvement = checks_without_improvement;
      s.open_fit = std::move(place);
      report.paused = true;
      break;
    }
  }
  if (!report.paused) {
    if (validation_size == 0) report.best_validation_mse = report.validation_mse;
    ++s.fits;
    RefreshPredictionWeights();
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

double EnsembleDynamics::TrainEpoch(const torch::Tensor& x, const torch::Tensor& y,
                                    const torch::Tensor& train_rows, std::int64_t subset) {
  State& s = *state_;
  const std::int64_t members = options_.ensemble_size;
  // Each member's own fresh subset of the train split, without replacement: (E, subset).
  std::vector<torch::Tensor> picks;
  for (std::int64_t m = 0; m < members; ++m) {
    picks.push_back(
        torch::randperm(train_rows.size(0), s.generator, torch::kLong).slice(0, 0, subset));
  }
  const torch::Tensor member_rows = train_rows.index({torch::stack(picks).to(s.device)});
  torch::Tensor epoch_loss = torch::zeros({}, torch::TensorOptions(s.device));
  double onednn_epoch_loss = 0.0;
  for (std::int64_t begin = 0; begin < subset; begin += options_.batch_size) {
    const std::int64_t end = std::min(begin + options_.batch_size, subset);
    const torch::Tensor batch = member_rows.slice(1, begin, end);  // (E, B)
    // Sum over members of each member's mean: every member gets its own MSE gradient.
    if (s.onednn_training) {
      // Each member's update on the thread that made its gradients, as soon as they are made: a
      // memory-bound pass beside the other members' products, not one of its own after them.
      s.optimizer->BeginStep();
      double batch_loss = 0.0;
      try {
        batch_loss = s.onednn_training->Gradients(
            s.weights, s.biases, x, y, batch,
            [&](std::int64_t m) { s.optimizer->StepPart(m, members); });
      } catch (...) {
        s.optimizer->EndStep();
        throw;
      }
      s.optimizer->EndStep();
      onednn_epoch_loss += batch_loss * static_cast<double>(end - begin);
    } else {
      const torch::Tensor prediction = Forward(x.index({batch}), false);  // (E, B, S)
      const torch::Tensor loss = (prediction - y.index({batch})).pow(2).mean({1, 2}).sum();
      loss.backward();  // Step() drops the gradients: nothing to zero
      epoch_loss += loss.detach() * static_cast<double>(end - begin);
      s.optimizer->Step();
    }
  }
  return (s.onednn_training ? onednn_epoch_loss : epoch_loss.item<double>()) /
         static_cast<double>(subset * members);
}

torch::Tensor EnsembleDynamics::NormalizeInputs(const torch::Tensor& inputs) const {
  return state_->input_normalizer.Normalize(inputs);
}

torch::Tensor EnsembleDynamics::DenormalizeInputs(const torch::Tensor& normalized) const {
  return state_->input_normalizer.Denormalize(normalized);
}

double EnsembleDynamics::PredictFlops(std::int64_t samples) const {
  double per_row = 0.0;
  for (const torch::Tensor& w : state_->weights) {
    per_row += 2.0 * static_cast<double>(w.size(1)) * static_cast<double>(w.size(2));
  }
  return per_row * static_cast<double>(samples) * options_.ensemble_size;
}

namespace {

// Header of a saved ensemble: the dimensions a file must match.
torch::Tensor Shape(int state_dim, int action_dim, const EnsembleOptions& options) {
  std::vector<std::int64_t> shape = {state_dim, action_dim, options.ensemble_size,
                                     options.predict_delta ? 1 : 0};
  shape.insert(shape.end(), options.hidden_sizes.begin(), options.hidden_sizes.end());
  return torch::tensor(shape, torch::kLong);
}

}  // namespace

void EnsembleDynamics::Save(const std::string& path) const {
  const State& s = *state_;
  torch::serialize::OutputArchive archive;
  archive.write("format", torch::tensor({1}, torch::kLong));
  archive.write("shape", Shape(state_dim_, action_dim_, options_));
  for (size_t l = 0; l < s.weights.size(); ++l) {
    archive.write("weight" + std::to_string(l), s.weights[l].detach().cpu());
    archive.write("bias" + std::to_string(l), s.biases[l].detach().cpu());
  }
  archive.write("input_mean", s.input_normalizer.mean().cpu());
  archive.write("input_std", s.input_normalizer.std().cpu());
  archive.write("target_mean", s.target_normalizer.mean().cpu());
  archive.write("target_std", s.target_normalizer.std().cpu());
  archive.write("generator", s.generator.get_state());
  archive.write("fits", torch::tensor({s.fits}, torch::kLong));
  torch::serialize::OutputArchive optimizer;
  s.optimizer->Save(optimizer);
  archive.write("adam", optimizer);
  if (s.open_fit) {
    const State::OpenFit& f = *s.open_fit;
    archive.write("open_fit_counts",
                  torch::tensor({f.rows, static_cast<std::int64_t>(f.next_epoch),
                                 static_cast<std::int64_t>(f.checks_without_improvement)},
                                torch::kLong));
    archive.write("open_fit_mse",
                  torch::tensor({f.validation_mse, f.best_validation_mse}, torch::kDouble));
    archive.write("open_fit_split_generator", f.split_generator);
  }
  SaveArchive(archive, path);
}

void EnsembleDynamics::Load(const std::string& path) {
  State& s = *state_;
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path);
  } catch (const c10::Error& error) {
    Fail("could not read an ensemble from '{}': {}", path, error.what_without_backtrace());
  }
  const auto read = [&archive, &path](const std::string& key) {
    torch::Tensor t;
    Require(archive.try_read(key, t), "'{}' is not a cmbrl ensemble file: it has no '{}'", path,
            key);
    return t;
  };
  const torch::Tensor shape = read("shape");
  const torch::Tensor expected = Shape(state_dim_, action_dim_, options_);
  Require(shape.sizes() == expected.sizes() && torch::equal(shape, expected),
          "ensemble file '{}' has shape {} (state, action, members, delta, hidden...), this "
          "ensemble is {}",
          path, c10::str(shape), c10::str(expected));
  {
    const torch::NoGradGuard no_grad;
    for (size_t l = 0; l < s.weights.size(); ++l) {
      s.weights[l].copy_(read("weight" + std::to_string(l)));
      s.biases[l].copy_(read("bias" + std::to_string(l)));
    }
  }
  s.input_normalizer.Set(read("input_mean").to(s.device), read("input_std").to(s.device));
  s.target_normalizer.Set(read("target_mean").to(s.device), read("target_std").to(s.device));
  s.generator.set_state(read("generator"));
  s.fits = static_cast<int>(read("fits").item<std::int64_t>());
  torch::serialize::InputArchive optimizer;
  Require(archive.try_read("adam", optimizer),
          "'{}' has no optimiser state 'adam'{}", path,
          archive.try_read("optimizer", optimizer)
              ? ": it was written by an older cmbrl whose optimiser state this version cannot "
                "read; start a new run"
              : "");
  s.optimizer->Load(optimizer, path);
  s.open_fit.reset();
  torch::Tensor counts;
  if (archive.try_read("open_fit_counts", counts)) {  // saved with a fit open (absent before v0.9)
    const torch::Tensor mse = read("open_fit_mse");
    Require(counts.numel() == 3 && counts.scalar_type() == torch::kLong && mse.numel() == 2 &&
                mse.scalar_type() == torch::kDouble,
            "'{}' has an open fit of another form", path);
    State::OpenFit f;
    f.rows = counts[0].item<std::int64_t>();
    f.next_epoch = static_cast<int>(counts[1].item<std::int64_t>());
    f.checks_without_improvement = static_cast<int>(counts[2].item<std::int64_t>());
    f.validation_mse = mse[0].item<double>();
    f.best_validation_mse = mse[1].item<double>();
    f.split_generator = read("open_fit_split_generator");
    Require(f.rows >= 2 && f.next_epoch >= 2 && f.next_epoch <= options_.max_epochs &&
                f.checks_without_improvement >= 0,
            "'{}' has an open fit at epoch {} of {} on {} transitions: not one this ensemble can "
            "go on with",
            path, f.next_epoch, options_.max_epochs, f.rows);
    s.open_fit = std::move(f);
  }
  RefreshPredictionWeights();
}

}  // namespace cmbrl

#include "cmbrl/models/xgboost_cost_model.h"

#include <torch/torch.h>
#include <xgboost/c_api.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/models/tree_ensemble_tensor.h"

namespace cmbrl {
namespace {

constexpr const char* kFileFormat = "cmbrl-xgboost-cost-model";

void XgbCheck(int status, const char* what) {
  Require(status == 0, "XGBoost {} failed: {}", what, XGBGetLastError());
}

struct DMatrixDeleter {
  void operator()(void* handle) const { XGDMatrixFree(handle); }
};
using DMatrixPtr = std::unique_ptr<void, DMatrixDeleter>;

DMatrixPtr MakeDMatrix(const float* rows, int count, int columns) {
  DMatrixHandle handle = nullptr;
  XgbCheck(XGDMatrixCreateFromMat(rows, count, columns, std::numeric_limits<float>::quiet_NaN(),
                                  &handle),
           "XGDMatrixCreateFromMat");
  return DMatrixPtr(handle);
}

// The training rows, the safe states then the unsafe ones, (safe_count + unsafe_count, width);
// throws cmbrl::Error naming a non-finite value by its row and column.
std::vector<float> TrainingRows(const float* safe, int safe_count, const float* unsafe,
                                int unsafe_count, size_t width) {
  std::vector<float> features(static_cast<size_t>(safe_count + unsafe_count) * width);
  std::copy_n(safe, static_cast<size_t>(safe_count) * width, features.begin());
  std::copy_n(unsafe, static_cast<size_t>(unsafe_count) * width,
              features.begin() + static_cast<size_t>(safe_count) * width);
  for (size_t i = 0; i < features.size(); ++i) {
    Require(std::isfinite(features[i]),
            "classifier training state {} has a non-finite value {} in column {}", i / width,
            features[i], i % width);
  }
  return features;
}

// XGBoost's parameters for the options (set up as the original's LightGBM, facts B4), starting
// from `base_score`.
std::vector<std::pair<const char*, std::string>> BoosterParams(const XgbCostModelOptions& o,
                                                               double base_score,
                                                               std::uint64_t seed) {
  return {
      {"objective", "binary:logistic"},
      {"booster", "gbtree"},
      {"eta", fmt::format("{}", o.learning_rate)},
      {"max_depth", std::to_string(o.max_depth)},
      {"max_leaves", std::to_string(o.max_leaves)},
      {"grow_policy", o.grow_policy},
      {"tree_method", o.tree_method},
      {"lambda", fmt::format("{}", o.l2_regularization)},
      {"min_child_weight", fmt::format("{}", o.min_child_weight)},
      {"base_score", fmt::format("{}", base_score)},
      {"nthread", std::to_string(o.threads == 0 ? CoreCount() : o.threads)},
      {"seed", std::to_string(seed % 2147483647ULL)},
      {"verbosity", "0"},
  };
}

}  // namespace

// Owns an XGBoost booster handle.
struct XgbCostModel::Booster {
  BoosterHandle handle = nullptr;
  ~Booster() {
    if (handle != nullptr) XGBoosterFree(handle);
  }
  std::string SaveJson() const {
    bst_ulong length = 0;
    const char* buffer = nullptr;
    XgbCheck(XGBoosterSaveModelToBuffer(handle, R"({"format": "json"})", &length, &buffer),
             "XGBoosterSaveModelToBuffer");
    return std::string(buffer, length);
  }
};

// The trees as tensors on the planner's device (absent on the CPU, where the flat loop is used).
class XgbCostModel::DeviceTrees {
 public:
  DeviceTrees(const FlatTreeEnsemble& trees, const torch::Device& device)
      : tensors(trees, device) {}
  TreeEnsembleTensors tensors;
};

XgbCostModel::XgbCostModel(int state_dim, XgbCostModelOptions options, std::uint64_t seed)
    : state_dim_(state_dim), options_(std::move(options)), seed_(seed) {
  Require(state_dim >= 1, "state_dim is {}: expected a positive number", state_dim);
  ValidateXgbCostModelOptions(options_);
  ParseDevice(options_.device);
  margin_threshold_ = static_cast<float>(std::log(options_.threshold / (1.0 - options_.threshold)));
}

XgbCostModel::~XgbCostModel() = default;

XgbCostModel::FitSet XgbCostModel::SelectFitSet(const LabeledStateBuffer& data) const {
  Require(data.state_dim() == state_dim_, "labeled states have {} dimensions, the model {}",
          data.state_dim(), state_dim_);
  FitSet set;
  set.unsafe_count = data.unsafe_size();
  set.safe_count = std::min(data.safe_size(), options_.safe_per_unsafe * set.unsafe_count + 1);
  set.safe = options_.safe_selection == "newest" ? data.NewestSafe(set.safe_count)
                                                 : data.LastSafeSlots(set.safe_count);
  set.unsafe = data.AllUnsafe();
  return set;
}

CostFitReport XgbCostModel::Fit(const LabeledStateBuffer& data,
                                const std::function<bool()>& keep_going) {
  const FitSet set = SelectFitSet(data);
  return FitArrays(set.safe.data(), set.safe_count, set.unsafe.data(), set.unsafe_count,
                   keep_going);
}

CostFitReport XgbCostModel::FitArrays(const float* safe, int safe_count, const float* unsafe,
                                      int unsafe_count, const std::function<bool()>& keep_going) {
  const auto start = std::chrono::steady_clock::now();
  Require(safe_count >= 0 && unsafe_count >= 0, "negative sample counts");
  CostFitReport report;
  report.safe_used = safe_count;
  report.unsafe_used = unsafe_count;
  if (unsafe_count == 0) {
    if (keep_going && !keep_going()) {
      report.interrupted = true;
      return report;
    }
    // Nothing unsafe seen yet: predict everything safe (see the class comment).
    Untrain();
    report.safe_accuracy = 1.0;
    report.unsafe_accuracy = std::numeric_limits<double>::quiet_NaN();
    return report;
  }

  const int rows = safe_count + unsafe_count;
  const std::vector<float> features =
      TrainingRows(safe, safe_count, unsafe, unsafe_count, static_cast<size_t>(state_dim_));
  std::vector<float> labels(rows, 0.0f);
  std::fill(labels.begin() + safe_count, labels.end(), 1.0f);
  const DMatrixPtr matrix = MakeDMatrix(features.data(), rows, state_dim_);
  XgbCheck(XGDMatrixSetFloatInfo(matrix.get(), "label", labels.data(), rows), "set labels");

  auto booster = std::make_unique<Booster>();
  DMatrixHandle matrices[] = {matrix.get()};
  XgbCheck(XGBoosterCreate(matrices, 1, &booster->handle), "XGBoosterCreate");
  // LightGBM starts from the log-odds of the label mean (boost_from_average); XGBoost 1.7 takes
  // that start as base_score, which must lie strictly inside (0, 1).
  const double base_score =
      options_.boost_from_average
          ? std::clamp(static_cast<double>(unsafe_count) / rows, 1e-6, 1.0 - 1e-6)
          : 0.5;
  for (const auto& [key, value] : BoosterParams(options_, base_score, seed_)) {
    XgbCheck(XGBoosterSetParam(booster->handle, key, value.c_str()), key);
  }
  for (int round = 0; round < options_.rounds; ++round) {
    XgbCheck(XGBoosterUpdateOneIter(booster->handle, round, matrix.get()),
             "XGBoosterUpdateOneIter");
    if (keep_going && !keep_going()) {
      report.interrupted = true;
      return report;
    }
  }
  booster_ = std::move(booster);
  AdoptBoosterJson(booster_->SaveJson());

  const std::vector<float> margins = Margins(features.data(), rows);
  int safe_right = 0, unsafe_right = 0;
  for (int i = 0; i < rows; ++i) {
    const bool violation = margins[i] > margin_threshold_;
    (i < safe_count ? safe_right : unsafe_right) += (violation == (i >= safe_count));
  }
  report.trained = true;
  report.trees = trees_.num_trees();
  report.safe_accuracy = safe_count > 0 ? static_cast<double>(safe_right) / safe_count
                                        : std::numeric_limits<double>::quiet_NaN();
  report.unsafe_accuracy = static_cast<double>(unsafe_right) / unsafe_count;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

void XgbCostModel::Untrain() {
  trained_ = false;
  booster_.reset();
  device_trees_.reset();
  trees_ = FlatTreeEnsemble();
}

void XgbCostModel::AdoptBoosterJson(const std::string& json) {
  trees_ = FlatTreeEnsemble::FromXgboostJson(json);
  Require(trees_.num_features() == state_dim_, "XGBoost model has {} features, expected {}",
          trees_.num_features(), state_dim_);
  const torch::Device device = ParseDevice(options_.device);
  device_trees_ = device.is_cpu() ? nullptr : std::make_unique<DeviceTrees>(trees_, device);
  trained_ = true;
}

std::vector<float> XgbCostModel::Margins(const float* states, int rows) const {
  Require(trained_, "the cost model has not been trained on any unsafe state yet");
  std::vector<float> margins(rows);
  trees_.Margins(states, rows, margins.data(), options_.predict_threads);
  return margins;
}

std::vector<float> XgbCostModel::XgboostMargins(const float* states, int rows) const {
  Require(trained_ && booster_ != nullptr, "the cost model has no trained booster");
  const DMatrixPtr matrix = MakeDMatrix(states, rows, state_dim_);
  bst_ulong length = 0;
  const float* result = nullptr;
  // Option mask 1: output margins (log-odds) rather than probabilities.
  XgbCheck(XGBoosterPredict(booster_->handle, matrix.get(), 1, 0, 0, &length, &result),
           "XGBoosterPredict");
  return std::vector<float>(result, result + length);
}

std::vector<std::uint8_t> XgbCostModel::PredictRows(const float* states, int rows) const {
  const size_t width = static_cast<size_t>(state_dim_);
  for (size_t i = 0; i < static_cast<size_t>(rows) * width; ++i) {
    Require(std::isfinite(states[i]),
            "state {} has a non-finite value {} in column {}: expected finite numbers", i / width,
            states[i], i % width);
  }
  std::vector<std::uint8_t> violations(rows, 0);
  if (!trained_) return violations;
  const std::vector<float> margins = Margins(states, rows);
  for (int i = 0; i < rows; ++i) violations[i] = margins[i] > margin_threshold_;
  return violations;
}

torch::Tensor XgbCostModel::PredictViolation(const torch::Tensor& states) const {
  const torch::Device device =
      device_trees_ ? device_trees_->tensors.device() : torch::Device(torch::kCPU);
  CheckFloatTensor(states, "states", state_dim_, device);
  std::vector<std::int64_t> batch_shape(states.sizes().begin(), states.sizes().end() - 1);
  if (!trained_) return torch::zeros(batch_shape, states.options());
  const torch::Tensor rows = states.reshape({-1, state_dim_}).contiguous();
  torch::Tensor margins;
  if (device_trees_) {
    margins = device_trees_->tensors.Margins(rows);
  } else {
    margins = torch::empty({rows.size(0)}, rows.options());
    trees_.Margins(rows.data_ptr<float>(), rows.size(0), margins.data_ptr<float>(),
                   options_.predict_threads);
  }
  return (margins > margin_threshold_).to(torch::kFloat).reshape(batch_shape);
}

void XgbCostModel::Save(const std::string& path) const {
  // The threshold is not written: it is a setting of whoever loads the trees (the run's config,
  // an evaluation's override), not of the trees. Files of earlier versions hold one; it is
  // ignored.
  nlohmann::json file = {
      {"format", kFileFormat}, {"version", 1}, {"state_dim", state_dim_}, {"trained", trained_}};
  if (trained_) file["booster"] = nlohmann::json::parse(booster_->SaveJson());
  WriteFile(path, file.dump());
}

void XgbCostModel::Load(const std::string& path) {
  std::ifstream in(path);
  Require(static_cast<bool>(in), "could not open the cost model file '{}'", path);
  nlohmann::json file;
  try {
    in >> file;
  } catch (const nlohmann::json::exception& error) {
    Fail("cost model file '{}' is not valid JSON: {}", path, error.what());
  }
  Require(file.is_object() && file.value("format", "") == kFileFormat,
          "'{}' is not a cmbrl cost model file (format '{}' expected)", path, kFileFormat);
  const int state_dim = file.value("state_dim", -1);
  Require(state_dim == state_dim_,
          "cost model file '{}' is for {} state dimensions, this model has {}", path, state_dim,
          state_dim_);
  if (!file.value("trained", false)) {
    Untrain();
    return;
  }
  const std::string json = file.at("booster").dump();
  auto booster = std::make_unique<Booster>();
  XgbCheck(XGBoosterCreate(nullptr, 0, &booster->handle), "XGBoosterCreate");
  XgbCheck(XGBoosterLoadModelFromBuffer(booster->handle, json.data(), json.size()),
           "XGBoosterLoadModelFromBuffer");
  booster_ = std::move(booster);
  AdoptBoosterJson(json);
}

}  // namespace cmbrl

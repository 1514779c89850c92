// `cmbrl bench models`: the learned models at the paper's sizes, each figure beside a matrix
// product rate measured in the same run.
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/bench_util.h"
#include "app/commands.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/tree_ensemble_tensor.h"
#include "cmbrl/models/xgboost_cost_model.h"

namespace cmbrl::app {
namespace {

struct ModelBenchArgs {
  int members = 4;          // paper: 4 (Point), 5 (Car)
  int samples = 500;        // rows per member for the forward pass (the planner's population)
  int state_dim = 24;       // PointGoal1 / CarGoal1
  int hidden = 1024;        // width of the 3 hidden layers
  int transitions = 50000;  // training set of one epoch
  int classifier_states = 40000;
  int predict_states = 20000;
  int runs = 3;
  std::uint64_t seed = 0;
};

using Clock = std::chrono::steady_clock;

// Median seconds of `runs` calls of `work`, after one warm-up call.
double MedianSeconds(int runs, const std::function<void()>& work) {
  work();
  std::vector<double> seconds;
  for (int i = 0; i < runs; ++i) {
    const auto start = Clock::now();
    work();
    seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  return Median(seconds);
}

void Print(nlohmann::ordered_json line) { std::cout << line.dump() << std::endl; }

// States shaped like PointGoal1's with 0/1 labels: unsafe when one of 7 ego-frame hazards lies
// within 0.2 m; each label class drawn until `count` rows hold a quarter unsafe.
void ClassifierData(int count, int dim, std::uint64_t seed, std::vector<float>& safe,
                    std::vector<float>& unsafe) {
  Rng rng(seed);
  const int unsafe_wanted = count / 4;
  int safe_rows = 0, unsafe_rows = 0;
  std::vector<float> row(dim);
  while (safe_rows + unsafe_rows < count) {
    bool violation = false;
    for (int i = 0; i < dim; ++i) row[i] = static_cast<float>(Uniform(rng, -2, 2));
    for (int h = 10; h + 1 < dim; h += 2) violation |= std::hypot(row[h], row[h + 1]) < 0.2;
    if (violation && unsafe_rows < unsafe_wanted) {
      unsafe.insert(unsafe.end(), row.begin(), row.end());
      ++unsafe_rows;
    } else if (!violation && safe_rows < count - unsafe_wanted) {
      safe.insert(safe.end(), row.begin(), row.end());
      ++safe_rows;
    }
  }
}

void RunModelBench(const ModelBenchArgs& args) {
  torch::manual_seed(args.seed);
  const std::int64_t gemm_n = 2048;
  const torch::Tensor a = torch::randn({gemm_n, gemm_n});
  const torch::Tensor b = torch::randn({gemm_n, gemm_n});
  const double gemm_seconds = MedianSeconds(5, [&] { torch::mm(a, b); });
  const double gemm_flops = 2.0 * gemm_n * gemm_n * gemm_n / gemm_seconds;
  Print({{"bench", "models"},
         {"what", "gemm_fp32"},
         {"n", gemm_n},
         {"median_ms", gemm_seconds * 1e3},
         {"gflops", gemm_flops / 1e9},
         {"torch_threads", at::get_num_threads()}});
  const auto rate = [gemm_flops](nlohmann::ordered_json& line, double flops, double seconds) {
    line["gflops"] = flops / seconds / 1e9;
    line["gemm_gflops"] = gemm_flops / 1e9;
    line["ratio_to_gemm"] = flops / seconds / gemm_flops;
  };

  // Ensemble forward: the planner's hot call.
  EnsembleOptions options;
  options.ensemble_size = args.members;
  options.hidden_sizes = {args.hidden, args.hidden, args.hidden};
  const int action_dim = 2;
  EnsembleDynamics ensemble(args.state_dim, action_dim, options, args.seed);
  const torch::Tensor states = torch::randn({args.members, args.samples, args.state_dim});
  const torch::Tensor actions = torch::rand({args.members, args.samples, action_dim}) * 2 - 1;
  const double forward_seconds =
      MedianSeconds(std::max(10, args.runs), [&] { ensemble.PredictUnchecked(states, actions); });
  nlohmann::ordered_json forward = {
      {"bench", "models"},       {"what", "ensemble_forward"},
      {"members", args.members}, {"samples", args.samples},
      {"hidden", args.hidden},   {"median_ms", forward_seconds * 1e3}};
  rate(forward, ensemble.PredictFlops(args.samples), forward_seconds);
  Print(forward);

  // One training epoch on `transitions` transitions (all members, batched).
  TransitionBuffer data(args.state_dim, action_dim, args.transitions);
  Rng rng(args.seed);
  std::vector<double> s(args.state_dim), u(action_dim), next(args.state_dim);
  for (int i = 0; i < args.transitions; ++i) {
    for (double& v : s) v = Uniform(rng, -1, 1);
    for (double& v : u) v = Uniform(rng, -1, 1);
    for (int j = 0; j < args.state_dim; ++j) next[j] = s[j] + 0.1 * u[j % action_dim];
    data.Add(s, u, next);
  }
  EnsembleOptions epoch_options = options;
  epoch_options.max_epochs = 1;
  EnsembleDynamics trainee(args.state_dim, action_dim, epoch_options, args.seed);
  EnsembleFitReport report;
  const double epoch_seconds = MedianSeconds(args.runs, [&] { report = trainee.Fit(data); });
  // Rows each member trains on per epoch; forward plus backward is about 3 forward passes.
  const std::int64_t rows =
      static_cast<std::int64_t>(options.member_subset_fraction * report.train_size);
  nlohmann::ordered_json epoch = {{"bench", "models"},
                                  {"what", "ensemble_train_epoch"},
                                  {"members", args.members},
                                  {"transitions", args.transitions},
                                  {"rows_per_member", rows},
                                  {"batch_size", options.batch_size},
                                  {"median_ms", epoch_seconds * 1e3}};
  rate(epoch, 3.0 * trainee.PredictFlops(rows), epoch_seconds);
  Print(epoch);

  // Classifier: fit on `classifier_states` states, then predict `predict_states`.
  std::vector<float> safe, unsafe;
  ClassifierData(args.classifier_states, args.state_dim, args.seed, safe, unsafe);
  const int safe_count = static_cast<int>(safe.size()) / args.state_dim;
  const int unsafe_count = static_cast<int>(unsafe.size()) / args.state_dim;
  XgbCostModel classifier(args.state_dim, XgbCostModelOptions{}, args.seed);
  CostFitReport fit;
  const double fit_seconds = MedianSeconds(args.runs, [&] {
    fit = classifier.FitArrays(safe.data(), safe_count, unsafe.data(), unsafe_count);
  });
  Print({{"bench", "models"},
         {"what", "classifier_fit"},
         {"states", safe_count + unsafe_count},
         {"unsafe", unsafe_count},
         {"trees", fit.trees},
         {"median_ms", fit_seconds * 1e3},
         {"unsafe_accuracy", fit.unsafe_accuracy},
         {"safe_accuracy", fit.safe_accuracy}});

  const int predict = std::min(args.predict_states, safe_count);
  std::vector<float> margins(predict);
  const double flat_seconds = MedianSeconds(std::max(5, args.runs), [&] {
    classifier.trees().Margins(safe.data(), predict, margins.data());
  });
  const torch::Tensor rows_tensor =
      torch::from_blob(safe.data(), {predict, args.state_dim}).clone();
  const TreeEnsembleTensors tensors(classifier.trees(), torch::Device(torch::kCPU));
  const double tensor_seconds =
      MedianSeconds(std::max(5, args.runs), [&] { tensors.Margins(rows_tensor); });
  const auto node_visits = [&](double seconds) {
    return static_cast<double>(predict) * fit.trees / seconds;
  };
  Print({{"bench", "models"},
         {"what", "classifier_predict_flat_cpu"},
         {"states", predict},
         {"median_ms", flat_seconds * 1e3},
         {"tree_evaluations_per_second", node_visits(flat_seconds)}});
  Print({{"bench", "models"},
         {"what", "classifier_predict_tensor_cpu"},
         {"states", predict},
         {"median_ms", tensor_seconds * 1e3},
         {"tree_evaluations_per_second", node_visits(tensor_seconds)}});
}

}  // namespace

void AddBenchModelsCommand(CLI::App& bench) {
  auto args = std::make_shared<ModelBenchArgs>();
  CLI::App* models = bench.add_subcommand(
      "models",
      "Ensemble forward and training epoch, classifier fit and prediction, beside the "
      "matrix-product rate of the same run");
  models->add_option("--members", args->members, "ensemble members")->capture_default_str();
  models->add_option("--samples", args->samples, "rows per member in the forward pass")
      ->capture_default_str();
  models->add_option("--state-dim", args->state_dim, "state dimension")->capture_default_str();
  models->add_option("--hidden", args->hidden, "width of the 3 hidden layers")
      ->capture_default_str();
  models->add_option("--transitions", args->transitions, "transitions of the training epoch")
      ->capture_default_str();
  models->add_option("--classifier-states", args->classifier_states, "states of the fit")
      ->capture_default_str();
  models->add_option("--predict-states", args->predict_states, "states to classify")
      ->capture_default_str();
  models->add_option("--runs", args->runs, "runs per figure; the median is reported")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  models->add_option("--seed", args->seed, "seed")->capture_default_str();
  for (CLI::Option* option : models->get_options()) {
    if (option->get_name() != "--help" && option->get_name() != "--seed") {
      option->check(CLI::PositiveNumber);
    }
  }
  models->callback([args] { RunModelBench(*args); });
}

}  // namespace cmbrl::app

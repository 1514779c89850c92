// `cmbrl bench plan` and `cmbrl bench train`: planning steps and model fits at a config's
// settings, each figure beside the matrix-product ceiling measured in the same run.
#include <torch/torch.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "app/bench_ceiling.h"
#include "app/bench_util.h"
#include "app/commands.h"
#include "cmbrl/agent/mpc_agent.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/env/goal_env.h"
#include "cmbrl/experiment/config.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/xgboost_cost_model.h"

namespace cmbrl::app {
namespace {

struct LearningBenchArgs {
  std::string config_path = "configs/pointgoal1-rce.yaml";
  std::string device;                  // empty: the config's
  std::vector<std::string> planners;   // empty: the config's
  int runs = 5;
  int transitions = 50000;             // bench train: the epoch's data
  int classifier_states = 40000;       // bench train: the classifier fit's data
  bool full_fit = false;               // bench train: also a whole fit (up to max_epochs)
  std::uint64_t seed = 0;
};

TrainConfig LoadBenchConfig(const LearningBenchArgs& args) {
  TrainConfig config = LoadTrainConfig(args.config_path);
  if (!args.device.empty()) {
    SetTrainDevice(config, args.device);
    ValidateTrainConfig(config, args.config_path);
  }
  return config;
}

// The config's task, for its state and action sizes and a start state.
struct TaskShape {
  int state_dim = 0;
  int action_dim = 0;
  std::vector<double> start;  // the observation after Reset(seed)
};

TaskShape ShapeOf(const TrainConfig& config, std::uint64_t seed) {
  GoalEnv env(GoalTaskSpecByName(config.task, ParseVariant(config.variant)));
  TaskShape shape;
  shape.state_dim = env.observation_spec().size();
  shape.action_dim = env.action_spec().size();
  shape.start = env.Reset(seed);
  return shape;
}

// A classifier at the config's settings fitted on hazard-shaped synthetic states, so that its
// trees have the size and depth the real runs see.
std::unique_ptr<XgbCostModel> FittedClassifier(const TrainConfig& config, int state_dim,
                                               int states, std::uint64_t seed,
                                               CostFitReport* report) {
  std::vector<float> safe, unsafe;
  ClassifierData(states, state_dim, seed, safe, unsafe);
  auto classifier = std::make_unique<XgbCostModel>(state_dim, config.classifier, seed);
  const CostFitReport fit =
      classifier->FitArrays(safe.data(), static_cast<int>(safe.size()) / state_dim, unsafe.data(),
                            static_cast<int>(unsafe.size()) / state_dim);
  if (report != nullptr) *report = fit;
  return classifier;
}

nlohmann::ordered_json Figure(const std::string& bench, const std::string& what,
                              const TrainConfig& config, const std::vector<double>& seconds) {
  const double median = Median(seconds);
  return {{"bench", bench},
          {"what", what},
          {"task", config.task},
          {"device", config.device},
          {"median_ms", median * 1e3},
          {"min_ms", *std::min_element(seconds.begin(), seconds.end()) * 1e3},
          {"max_ms", *std::max_element(seconds.begin(), seconds.end()) * 1e3},
          {"runs", seconds.size()}};
}

// Adds the FLOP rate and the ratio of the floor (flops at the ceiling's rate) to the median.
void AddRate(nlohmann::ordered_json& line, double flops, double ceiling) {
  const double seconds = line["median_ms"].get<double>() / 1e3;
  line["gflop"] = flops / 1e9;
  line["gflops"] = flops / seconds / 1e9;
  line["ceiling_gflops"] = ceiling / 1e9;
  line["floor_ms"] = flops / ceiling * 1e3;
  line["ratio_to_ceiling"] = flops / seconds / ceiling;
}

void RunPlanBench(const LearningBenchArgs& args) {
  const TrainConfig config = LoadBenchConfig(args);
  const torch::Device device = ParseDevice(config.device);
  const GemmCeilings ceilings = MeasureGemmCeilings(device, args.runs);
  const TaskShape shape = ShapeOf(config, args.seed);
  EnsembleDynamics ensemble(shape.state_dim, shape.action_dim, config.ensemble,
                            DeriveSeed(args.seed, kEnsembleSeedStream));
  const std::unique_ptr<XgbCostModel> classifier = FittedClassifier(
      config, shape.state_dim, 4000, DeriveSeed(args.seed, kClassifierSeedStream), nullptr);
  PlannerSettings settings = config.planning;
  settings.problem.action_dim = shape.action_dim;
  const std::int64_t members = config.ensemble.ensemble_size;
  const std::int64_t horizon = settings.problem.horizon;

  const std::vector<std::string> planners =
      args.planners.empty() ? std::vector<std::string>{config.planner} : args.planners;
  for (const std::string& planner : planners) {
    MpcAgent agent(ensemble, *classifier, planner, settings, config.objective,
                   DeriveSeed(args.seed, kPlannerSeedStream));
    const std::vector<double> step_seconds = TimeRuns(args.runs, [&] { agent.Act(shape.start); });
    const bool random = planner == "random";
    const std::int64_t population =
        random ? settings.random.samples : settings.cross_entropy.population;
    const int iterations = random ? 1 : settings.cross_entropy.max_iterations;
    const std::int64_t forwards = iterations * horizon;
    const double flops = ensemble.PredictFlops(population) * static_cast<double>(forwards);

    // The same work in parts: the ensemble's forward passes alone, and the classifier on as
    // many states (per member for RCE, the mean trajectory for CEM and random).
    const auto floats = torch::TensorOptions(device).dtype(torch::kFloat);
    const torch::Tensor states = torch::randn({members, population, shape.state_dim}, floats);
    const torch::Tensor actions = torch::rand({members, population, shape.action_dim}, floats);
    const double forward_seconds = MedianSeconds(args.runs, [&] {
      const torch::NoGradGuard no_grad;
      for (std::int64_t i = 0; i < forwards; ++i) ensemble.PredictUnchecked(states, actions);
      Synchronize(device);
    });
    const torch::Tensor scored = planner == "rce" ? states : states.narrow(0, 0, 1).contiguous();
    const double classifier_seconds = MedianSeconds(args.runs, [&] {
      for (std::int64_t i = 0; i < forwards; ++i) classifier->PredictViolation(scored);
      Synchronize(device);
    });

    nlohmann::ordered_json line = Figure("plan", "plan_step", config, step_seconds);
    line["planner"] = planner;
    line["members"] = members;
    line["hidden"] = config.ensemble.hidden_sizes;
    line["population"] = population;
    line["iterations"] = iterations;
    line["horizon"] = horizon;
    line["classifier_trees"] = classifier->trees().num_trees();
    line["classified_states"] = scored.size(0) * population * forwards;
    line["dynamics_forward_ms"] = forward_seconds * 1e3;
    line["classifier_ms"] = classifier_seconds * 1e3;
    AddRate(line, flops, ceilings.fp32);
    PrintJsonLine(line);
  }
}

void RunTrainBench(const LearningBenchArgs& args) {
  const TrainConfig config = LoadBenchConfig(args);
  const torch::Device device = ParseDevice(config.device);
  const GemmCeilings ceilings = MeasureGemmCeilings(device, args.runs);
  const TaskShape shape = ShapeOf(config, args.seed);

  // Synthetic transitions: the time of an epoch does not depend on what the data says.
  TransitionBuffer data(shape.state_dim, shape.action_dim, args.transitions);
  Rng rng(args.seed);
  std::vector<double> s(shape.state_dim), u(shape.action_dim), next(shape.state_dim);
  for (int i = 0; i < args.transitions; ++i) {
    for (double& v : s) v = Uniform(rng, -1, 1);
    for (double& v : u) v = Uniform(rng, -1, 1);
    for (int j = 0; j < shape.state_dim; ++j) next[j] = s[j] + 0.1 * u[j % shape.action_dim];
    data.Add(s, u, next);
  }
  // One epoch: every member trains on its subset in one batched step per batch; forward plus
  // backward costs about 3 forward passes.
  EnsembleOptions epoch_options = config.ensemble;
  epoch_options.max_epochs = 1;
  EnsembleDynamics trainee(shape.state_dim, shape.action_dim, epoch_options, args.seed);
  EnsembleFitReport report;
  const std::vector<double> epoch_seconds = TimeRuns(args.runs, [&] {
    report = trainee.Fit(data);
    Synchronize(device);
  });
  const auto rows =
      static_cast<std::int64_t>(config.ensemble.member_subset_fraction * report.train_size);
  nlohmann::ordered_json epoch = Figure("train", "dynamics_epoch", config, epoch_seconds);
  epoch["members"] = config.ensemble.ensemble_size;
  epoch["hidden"] = config.ensemble.hidden_sizes;
  epoch["transitions"] = args.transitions;
  epoch["rows_per_member"] = rows;
  epoch["batch_size"] = config.ensemble.batch_size;
  AddRate(epoch, 3.0 * trainee.PredictFlops(rows), ceilings.fp32);
  PrintJsonLine(epoch);

  if (args.full_fit) {
    EnsembleDynamics fitted(shape.state_dim, shape.action_dim, config.ensemble, args.seed);
    const std::vector<double> fit_seconds = TimeRuns(1, [&] {
      report = fitted.Fit(data);
      Synchronize(device);
    });
    nlohmann::ordered_json fit = Figure("train", "dynamics_fit", config, fit_seconds);
    fit["epochs"] = report.epochs;
    fit["max_epochs"] = config.ensemble.max_epochs;
    AddRate(fit, 3.0 * fitted.PredictFlops(rows) * report.epochs, ceilings.fp32);
    PrintJsonLine(fit);
  }

  CostFitReport fit;
  const std::vector<double> classifier_seconds = TimeRuns(args.runs, [&] {
    FittedClassifier(config, shape.state_dim, args.classifier_states, args.seed, &fit);
  });
  nlohmann::ordered_json line = Figure("train", "classifier_fit", config, classifier_seconds);
  line["states"] = fit.safe_used + fit.unsafe_used;
  line["unsafe"] = fit.unsafe_used;
  line["trees"] = fit.trees;
  line["unsafe_accuracy"] = fit.unsafe_accuracy;
  line["safe_accuracy"] = fit.safe_accuracy;
  PrintJsonLine(line);
}

void AddCommonOptions(CLI::App& command, LearningBenchArgs& args) {
  command.add_option("--config", args.config_path, "training config (YAML) whose settings to use")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  command.add_option("--device", args.device, "cpu, cuda or cuda:N (default: the config's)");
  command.add_option("--runs", args.runs, "runs per figure; the median is reported")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command.add_option("--seed", args.seed, "seed")->capture_default_str();
}

}  // namespace

void AddBenchLearningCommands(CLI::App& bench) {
  auto plan_args = std::make_shared<LearningBenchArgs>();
  CLI::App* plan = bench.add_subcommand(
      "plan",
      "Time of one MPC planning step (the action's copy to the host included) at a config's "
      "settings, with its dynamics and classifier parts, beside the matrix-product floor");
  AddCommonOptions(*plan, *plan_args);
  plan->add_option("--planners", plan_args->planners, "rce, cem, random (default: the config's)")
      ->check(CLI::IsMember(PlannerNames()));
  plan->callback([plan_args] { RunPlanBench(*plan_args); });

  auto train_args = std::make_shared<LearningBenchArgs>();
  train_args->runs = 3;
  CLI::App* train = bench.add_subcommand(
      "train",
      "Time of one dynamics training epoch and of a classifier fit at a config's settings, "
      "beside the matrix-product floor");
  AddCommonOptions(*train, *train_args);
  train->add_option("--transitions", train_args->transitions, "transitions of the epoch")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  train->add_option("--classifier-states", train_args->classifier_states,
                    "states of the classifier fit")
      ->check(CLI::Range(4, 1 << 30))
      ->capture_default_str();
  train->add_flag("--full-fit", train_args->full_fit,
                  "also time one whole fit, up to the config's max_epochs");
  train->callback([train_args] { RunTrainBench(*train_args); });
}

}  // namespace cmbrl::app

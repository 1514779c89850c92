#include "bench/learning_bench.h"

#include <torch/torch.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_util.h"
#include "bench/ceiling.h"
#include "bench/kernel_ceiling.h"
#include "cmbrl/agent/policy.h"
#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/learners/mpc/mpc_agent.h"
#include "cmbrl/learners/mpc/mpc_parts.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/fused_adam.h"
#include "cmbrl/models/onednn_forward.h"
#include "cmbrl/models/tree_ensemble_tensor.h"
#include "cmbrl/models/xgboost_cost_model.h"

namespace cmbrl::bench {
namespace {


TrainConfig LoadBenchConfig(const LearningBenchOptions& args) {
  const std::string source = fmt::format("{}", fmt::join(args.config_paths, " + "));
  // Defaults alone would be the paper's PointGoal1: a family overlay given alone is a slip.
  Require(ConfigFilesNameKey(args.config_paths, "task"),
          "'{}' names no task: give a task's preset first, e.g. --config "
          "configs/pointgoal1-rce.yaml {}",
          source, args.config_paths.back());
  TrainConfig config = LoadTrainConfig(args.config_paths);
  if (!args.device.empty()) {
    SetTrainDevice(config, args.device);
    ValidateTrainConfig(config, source);
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
  const std::unique_ptr<Env> env = MakeEnv(config.task, config.variant, config.spawn);
  TaskShape shape;
  shape.state_dim = env->observation_spec().size();
  shape.action_dim = env->action_spec().size();
  shape.start = env->Reset(seed);
  return shape;
}

// The ensemble's layer widths at the config's settings: [state + action, hidden..., state].
std::vector<std::int64_t> LayerSizes(const TrainConfig& config, const TaskShape& shape) {
  std::vector<std::int64_t> sizes = {shape.state_dim + shape.action_dim};
  sizes.insert(sizes.end(), config.ensemble.hidden_sizes.begin(),
               config.ensemble.hidden_sizes.end());
  sizes.push_back(shape.state_dim);
  return sizes;
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

// Wall seconds of each run and the ceiling measured just before it.
struct TimedRuns {
  std::vector<double> seconds;
  std::vector<double> ceilings;  // FLOP/s
};

// `runs` rounds over `works` after one warm-up of each, every run preceded by a ceiling probe;
// the works alternate run by run, so that a slow phase of the machine falls on all of them.
std::vector<TimedRuns> TimeAlternatingBesideCeiling(
    int runs, const std::function<double()>& probe,
    const std::vector<std::function<void()>>& works) {
  for (const auto& work : works) work();
  std::vector<TimedRuns> timed(works.size());
  for (int i = 0; i < runs; ++i) {
    for (std::size_t w = 0; w < works.size(); ++w) {
      timed[w].ceilings.push_back(probe());
      timed[w].seconds.push_back(SecondsOf(works[w]));
    }
  }
  return timed;
}

// `runs` runs of `work` after one warm-up, each preceded by a ceiling probe.
TimedRuns TimeRunsBesideCeiling(int runs, const std::function<double()>& probe,
                                 const std::function<void()>& work) {
  return TimeAlternatingBesideCeiling(runs, probe, {work}).front();
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

// Adds the FLOP rate, the ceiling (median of the probes), the floor (flops at that rate) and
// the ratio to the ceiling: the median of the runs' ratios to their own probes.
void AddRate(nlohmann::ordered_json& line, double flops, const TimedRuns& timed) {
  std::vector<double> ratios;
  for (size_t i = 0; i < timed.seconds.size(); ++i) {
    ratios.push_back(flops / timed.seconds[i] / timed.ceilings[i]);
  }
  const double ceiling = Median(timed.ceilings);
  line["gflop"] = flops / 1e9;
  line["gflops"] = flops / Median(timed.seconds) / 1e9;
  line["ceiling_gflops"] = ceiling / 1e9;
  line["floor_ms"] = flops / ceiling * 1e3;
  line["ratio_to_ceiling"] = Median(ratios);
}

// Random-policy transitions of the config's task: the data of the precision comparison's fit,
// and its start states.
TransitionBuffer RandomPolicyData(const TrainConfig& config, int steps, std::uint64_t seed) {
  const std::unique_ptr<Env> env = MakeEnv(config.task, config.variant, config.spawn);
  RandomPolicy policy(env->action_spec(), seed);
  TransitionBuffer data(env->observation_spec().size(), env->action_spec().size(), steps);
  std::vector<double> observation = env->Reset(seed);
  for (int step = 0; step < steps; ++step) {
    const std::vector<double> action = policy.Act(observation);
    StepResult result = env->Step(action);
    data.Add(observation, action, result.observation);
    observation = result.terminated || result.truncated ? env->Reset() : result.observation;
  }
  return data;
}

// One arithmetic of the predictions: a precision on a backend.
struct Variant {
  std::string precision, backend;
};

// Ensembles of the config's settings that differ only in arithmetic, with the same weights:
// random ones for a single variant, else fitted on random-policy data (a few epochs), so that
// the errors are those of a model that predicts something.
std::vector<std::unique_ptr<EnsembleDynamics>> EnsemblesByVariant(
    const TrainConfig& config, const std::vector<Variant>& variants, const TaskShape& shape,
    const TransitionBuffer* data, std::uint64_t seed) {
  std::vector<std::unique_ptr<EnsembleDynamics>> ensembles;
  for (const Variant& variant : variants) {
    EnsembleOptions options = config.ensemble;
    options.precision = variant.precision;
    options.backend = variant.backend;
    options.max_epochs = std::min(options.max_epochs, 5);
    ensembles.push_back(std::make_unique<EnsembleDynamics>(
        shape.state_dim, shape.action_dim, options, DeriveSeed(seed, kEnsembleSeedStream)));
  }
  if (data != nullptr) {
    ensembles[0]->Fit(*data);
    const std::string path =
        (std::filesystem::temp_directory_path() / fmt::format("cmbrl-bench-{}.pt", getpid()))
            .string();
    ensembles[0]->Save(path);
    for (size_t i = 1; i < ensembles.size(); ++i) ensembles[i]->Load(path);
    std::filesystem::remove(path);
  }
  return ensembles;
}

// Mean absolute value of a tensor, on the host.
double MeanAbs(const torch::Tensor& t) { return t.abs().mean().item<double>(); }

// Errors of `reduced` against `reference` (same weights): one-step and H-step predictions from
// recorded states under random actions, relative to the predicted change of the state; and the
// first actions MPC chooses from `agreement_states` recorded states with the same seed.
nlohmann::ordered_json PrecisionErrors(const TrainConfig& config, const std::string& planner,
                                       const PlannerSettings& settings, const CostModel& classifier,
                                       const EnsembleDynamics& reference,
                                       const EnsembleDynamics& reduced,
                                       const TransitionBuffer& data, int agreement_states,
                                       std::uint64_t seed) {
  const torch::NoGradGuard no_grad;
  const torch::Device device = ParseDevice(config.device);
  const std::int64_t members = config.ensemble.ensemble_size;
  const std::int64_t rows = std::min<std::int64_t>(data.size(), 500);
  const torch::Tensor recorded =
      torch::from_blob(const_cast<float*>(data.states()), {rows, data.state_dim()}).clone();
  const torch::Tensor start =
      recorded.to(device).unsqueeze(0).expand({members, rows, data.state_dim()}).contiguous();
  at::Generator generator = MakeCpuGenerator(seed);
  const std::int64_t horizon = settings.problem.horizon;
  const torch::Tensor actions =
      (torch::rand({horizon, members, rows, data.action_dim()}, generator) * 2 - 1).to(device);
  torch::Tensor ours = start, theirs = start;
  double one_step = 0.0;
  for (std::int64_t t = 0; t < horizon; ++t) {
    theirs = reference.PredictUnchecked(theirs, actions[t]);
    ours = reduced.PredictUnchecked(ours, actions[t]);
    if (t == 0) one_step = MeanAbs(ours - theirs) / MeanAbs(theirs - start);
  }
  const double horizon_error = MeanAbs(ours - theirs) / MeanAbs(theirs - start);

  MpcAgent reference_agent(reference, classifier, planner, settings, config.objective,
                           RewardTermFor(config), seed);
  MpcAgent reduced_agent(reduced, classifier, planner, settings, config.objective,
                         RewardTermFor(config), seed);
  double difference = 0.0;
  int close = 0;
  const int states = static_cast<int>(std::min<std::int64_t>(agreement_states, data.size()));
  for (int i = 0; i < states; ++i) {
    const std::int64_t row = i * (data.size() / states);
    const float* s = data.states() + row * data.state_dim();
    const std::vector<double> observation(s, s + data.state_dim());
    const std::vector<double> a = reference_agent.Act(observation);
    const std::vector<double> b = reduced_agent.Act(observation);
    double largest = 0.0;
    for (size_t j = 0; j < a.size(); ++j) {
      difference += std::abs(a[j] - b[j]) / static_cast<double>(a.size() * states);
      largest = std::max(largest, std::abs(a[j] - b[j]));
    }
    close += largest < 0.1;
  }
  return {{"one_step_relative_error", one_step},
          {"horizon_relative_error", horizon_error},
          {"action_mean_abs_difference", difference},
          {"actions_within_0_1", static_cast<double>(close) / states},
          {"agreement_states", states}};
}

// The optimiser's step on parameters of the ensemble's shapes (every layer's stacked weights
// and biases), as a training batch ends: one pass that reads each parameter, its gradient and
// its two moments and writes three of them back. Timed beside a pass over the same memory with
// the same reads and writes and next to no arithmetic (p += s g, m = b m + g, v = b v + g) on the
// same cores: the memory's ceiling for this pass. A CPU figure (FusedAdam's loop); on a GPU the
// step is tensor operations.
nlohmann::ordered_json AdamStepFigure(const TrainConfig& config, const TaskShape& shape, int runs) {
  const torch::NoGradGuard no_grad;
  const std::int64_t members = config.ensemble.ensemble_size;
  const std::vector<std::int64_t> sizes = LayerSizes(config, shape);
  std::vector<torch::Tensor> parameters, gradients;
  std::int64_t elements = 0;
  for (std::size_t l = 0; l + 1 < sizes.size(); ++l) {
    for (const std::vector<std::int64_t>& dims :
         {std::vector<std::int64_t>{members, sizes[l], sizes[l + 1]},
          std::vector<std::int64_t>{members, 1, sizes[l + 1]}}) {
      parameters.push_back(torch::randn(dims) * 0.01);
      gradients.push_back(torch::randn(dims) * 0.01);
      elements += parameters.back().numel();
    }
  }
  FusedAdam adam(parameters, FusedAdamOptions{});
  constexpr int kSteps = 10;  // steps per timed run
  const auto adam_steps = [&] {
    for (int k = 0; k < kSteps; ++k) {
      for (std::size_t i = 0; i < parameters.size(); ++i)
        parameters[i].mutable_grad() = gradients[i];
      adam.Step();
    }
  };
  // The same passes with next to no arithmetic, split over the cores as FusedAdam splits them.
  std::vector<torch::Tensor> m, v;
  for (const torch::Tensor& p : parameters) {
    m.push_back(torch::zeros_like(p));
    v.push_back(torch::zeros_like(p));
  }
  const auto bare_passes = [&] {
    for (int k = 0; k < kSteps; ++k) {
      for (std::size_t i = 0; i < parameters.size(); ++i) {
        float* p = parameters[i].data_ptr<float>();
        const float* g = gradients[i].data_ptr<float>();
        float* mi = m[i].data_ptr<float>();
        float* vi = v[i].data_ptr<float>();
        const std::int64_t n = parameters[i].numel();
        ParallelRanges(n, FusedAdamWorkers(n), [&](std::int64_t begin, std::int64_t end) {
          for (std::int64_t e = begin; e < end; ++e) {
            p[e] += 1e-7f * g[e];
            mi[e] = 0.5f * mi[e] + g[e];
            vi[e] = 0.5f * vi[e] + g[e];
          }
        });
      }
    }
  };
  const std::vector<TimedRuns> timed =
      TimeAlternatingBesideCeiling(runs, [] { return 0.0; }, {adam_steps, bare_passes});
  std::vector<double> step_seconds, bare_seconds, ratios;
  for (std::size_t r = 0; r < timed[0].seconds.size(); ++r) {
    step_seconds.push_back(timed[0].seconds[r] / kSteps);
    bare_seconds.push_back(timed[1].seconds[r] / kSteps);
    ratios.push_back(timed[1].seconds[r] / timed[0].seconds[r]);
  }
  const double bytes = 7.0 * sizeof(float) * static_cast<double>(elements);
  nlohmann::ordered_json line = Figure("train", "adam_step", config, step_seconds);
  line["parameters"] = elements;
  line["threads"] = CoreCount();
  line["gbytes"] = bytes / 1e9;
  line["gbytes_per_s"] = bytes / Median(step_seconds) / 1e9;
  line["ceiling_gbytes_per_s"] = bytes / Median(bare_seconds) / 1e9;
  line["ratio_to_ceiling"] = Median(ratios);
  return line;
}

}  // namespace

void RunPlanBench(const LearningBenchOptions& args, const FigureSink& emit) {
  const TrainConfig config = LoadBenchConfig(args);
  const torch::Device device = ParseDevice(config.device);
  GemmCeilings(device, args.runs, emit);
  const TaskShape shape = ShapeOf(config, args.seed);
  const std::vector<std::string> precisions =
      args.precisions.empty() ? std::vector<std::string>{config.ensemble.precision}
                              : args.precisions;
  const std::vector<std::string> backends =
      args.backends.empty() ? std::vector<std::string>{config.ensemble.backend} : args.backends;
  std::vector<Variant> variants;
  for (const std::string& precision : precisions) {
    for (const std::string& backend : backends) variants.push_back({precision, backend});
  }
  const bool compare = variants.size() > 1;
  std::unique_ptr<TransitionBuffer> data;
  if (compare) {
    data = std::make_unique<TransitionBuffer>(RandomPolicyData(config, args.fit_steps, args.seed));
  }
  const std::vector<std::unique_ptr<EnsembleDynamics>> ensembles =
      EnsemblesByVariant(config, variants, shape, data.get(), args.seed);
  const std::unique_ptr<XgbCostModel> classifier = FittedClassifier(
      config, shape.state_dim, 4000, DeriveSeed(args.seed, kClassifierSeedStream), nullptr);
  const PlannerSettings settings = PlannerSettingsFor(config, shape.action_dim);
  const std::int64_t members = config.ensemble.ensemble_size;
  const std::int64_t horizon = settings.problem.horizon;

  const std::vector<std::string> planners =
      args.planners.empty() ? std::vector<std::string>{config.planner} : args.planners;
  for (const std::string& planner : planners) {
    for (size_t p = 0; p < variants.size(); ++p) {
      const EnsembleDynamics& ensemble = *ensembles[p];
      MpcAgent agent(ensemble, *classifier, planner, settings, config.objective,
                     RewardTermFor(config), DeriveSeed(args.seed, kPlannerSeedStream));
      const PlannerEntry& entry = FindPlanner(planner);
      const PlanWork work = entry.work(settings);
      // The ceiling is read on the largest iteration's products (a planner whose population
      // shrinks runs its later iterations on smaller, slower-per-FLOP ones).
      const std::int64_t population = work.largest();
      // On the CPU the ceiling is the fastest kernel here on this step's own products; on CUDA
      // a large square product at the precision.
      std::unique_ptr<ShapeCeiling> shape_ceiling;
      std::unique_ptr<CeilingProbe> square_ceiling;
      std::function<double()> probe;
      if (device.is_cpu()) {
        shape_ceiling = std::make_unique<ShapeCeiling>(
            ForwardShapes(members, population, LayerSizes(config, shape)),
            variants[p].precision == "bf16" ? "bf16" : "fp32", args.runs);
        probe = [&] { return shape_ceiling->Measure(); };
      } else {
        square_ceiling = std::make_unique<CeilingProbe>(device, variants[p].precision);
        probe = [&] { return square_ceiling->Measure(); };
      }
      agent.Act(shape.start);  // a planner that carries elites from plan to plan now has some
      const TimedRuns step = TimeRunsBesideCeiling(args.runs, probe, [&] {
        agent.Act(shape.start);  // ends with the action's copy to the host
      });
      const int iterations = work.iterations();
      double flops = 0;
      for (const std::int64_t samples : work.samples) {
        flops += ensemble.PredictFlops(samples) * static_cast<double>(horizon);
      }

      // The same work in parts, called as the objective calls it: the ensemble's forward passes
      // one horizon step at a time, and the classifier once an iteration on all H steps' states
      // (per member for RCE, the mean trajectory for CEM and random).
      const auto floats = torch::TensorOptions(device).dtype(torch::kFloat);
      const torch::Tensor states = torch::randn({members, population, shape.state_dim}, floats);
      const torch::Tensor actions = torch::rand({members, population, shape.action_dim}, floats);
      const double forward_seconds = MedianSeconds(args.runs, [&] {
        const torch::NoGradGuard no_grad;
        for (const std::int64_t samples : work.samples) {
          const torch::Tensor s = states.narrow(1, 0, samples).contiguous();
          const torch::Tensor a = actions.narrow(1, 0, samples).contiguous();
          for (std::int64_t i = 0; i < horizon; ++i) ensemble.PredictUnchecked(s, a);
        }
        Synchronize(device);
      });
      const std::int64_t scored_members =
          entry.propagation == Propagation::kPerMember ? members : 1;
      const torch::Tensor scored =
          torch::randn({horizon, scored_members, population, shape.state_dim}, floats);
      const double classifier_seconds = MedianSeconds(args.runs, [&] {
        for (const std::int64_t samples : work.samples) {
          classifier->PredictViolation(scored.narrow(2, 0, samples).contiguous());
        }
        Synchronize(device);
      });

      // On a GPU: which path the trees took, and where it is the CUDA kernel, the tensor
      // operations' time on the same states and whether the kernel gave the host's bits.
      nlohmann::ordered_json classifier_paths = nlohmann::ordered_json::object();
      if (!device.is_cpu() && classifier->trained()) {
        const TreeEnsembleTensors fastest(classifier->trees(), device);
        classifier_paths["classifier_path"] =
            fastest.uses_cuda_kernel() ? "cuda kernel" : "tensor ops";
        if (fastest.uses_cuda_kernel()) {
          const TreeEnsembleTensors ops(classifier->trees(), device, 0, DeviceTreePath::kTensorOps);
          const torch::Tensor rows = scored.reshape({-1, shape.state_dim});
          classifier_paths["classifier_tensor_ops_ms"] =
              1e3 * MedianSeconds(args.runs, [&] {
                for (const std::int64_t samples : work.samples) {
                  ops.Margins(scored.narrow(2, 0, samples).reshape({-1, shape.state_dim}));
                }
                Synchronize(device);
              });
          const torch::Tensor host_rows = rows.cpu().contiguous();
          torch::Tensor host = torch::empty({host_rows.size(0)});
          classifier->trees().Margins(host_rows.data_ptr<float>(), host_rows.size(0),
                                      host.data_ptr<float>());
          classifier_paths["classifier_kernel_equals_host"] =
              torch::equal(fastest.Margins(rows).cpu(), host);
        }
      }

      nlohmann::ordered_json line = Figure("plan", "plan_step", config, step.seconds);
      line["planner"] = planner;
      line["precision"] = variants[p].precision;
      line["backend"] = ensemble.backend();
      // oneDNN's rows per prediction task on this CPU: it sets both the speed and the bits.
      if (ensemble.backend() == "onednn") line["block_rows"] = OnednnPredictionBlockRows();
      line["members"] = members;
      line["hidden"] = config.ensemble.hidden_sizes;
      line["population"] = population;
      line["samples_per_iteration"] = work.samples;
      line["samples_per_step"] = work.total();
      line["iterations"] = iterations;
      line["horizon"] = horizon;
      line["classifier_trees"] = classifier->trees().num_trees();
      line["classified_states"] = work.total() * horizon * scored_members;
      line["dynamics_forward_ms"] = forward_seconds * 1e3;
      line["classifier_ms"] = classifier_seconds * 1e3;
      line.update(classifier_paths);
      AddRate(line, flops, step);
      if (shape_ceiling) line["ceiling_candidates"] = shape_ceiling->candidates();
      if (p > 0) {
        line["error_against"] = variants[0].precision + "/" + ensembles[0]->backend();
        line["weights"] = fmt::format("fitted for {} epochs on {} random-policy transitions",
                                      std::min(config.ensemble.max_epochs, 5), args.fit_steps);
        line.update(PrecisionErrors(config, planner, settings, *classifier, *ensembles[0],
                                    ensemble, *data, args.agreement_states,
                                    DeriveSeed(args.seed, kPlannerSeedStream)));
      }
      emit(line);
    }
  }
}

void RunTrainBench(const LearningBenchOptions& args, const FigureSink& emit) {
  const TrainConfig config = LoadBenchConfig(args);
  const torch::Device device = ParseDevice(config.device);
  GemmCeilings(device, args.runs, emit);
  const TaskShape shape = ShapeOf(config, args.seed);
  // Training runs in float32, on TF32 tensor cores when the config asks for them.
  CeilingProbe probe(device, config.ensemble.precision == "tf32" ? "tf32" : "fp32");

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
  // Which kernel is fastest on one training batch's forward products (the backward pass's two
  // products per layer have the same sizes): the per-shape ceiling beside the GEMM one.
  nlohmann::ordered_json batch_candidates;
  if (device.is_cpu()) {
    const ShapeCeiling batch(
        ForwardShapes(config.ensemble.ensemble_size, config.ensemble.batch_size,
                      LayerSizes(config, shape)), "fp32",
        args.runs);
    batch_candidates = batch.candidates();
  }
  // One epoch per backend, alternating them run by run: every member trains on its subset in
  // one step per batch; forward plus backward costs about 3 forward passes.
  const std::vector<std::string> backends =
      args.backends.empty() ? std::vector<std::string>{config.ensemble.backend} : args.backends;
  std::vector<std::unique_ptr<EnsembleDynamics>> trainees;
  EnsembleFitReport report;
  std::vector<std::function<void()>> epochs;
  for (const std::string& backend : backends) {
    EnsembleOptions epoch_options = config.ensemble;
    epoch_options.max_epochs = 1;
    epoch_options.backend = backend;
    trainees.push_back(std::make_unique<EnsembleDynamics>(shape.state_dim, shape.action_dim,
                                                          epoch_options, args.seed));
    epochs.push_back([&report, &device, &trainee = *trainees.back(), &data] {
      report = trainee.Fit(data);
      Synchronize(device);
    });
  }
  const std::vector<TimedRuns> epoch_runs =
      TimeAlternatingBesideCeiling(args.runs, [&] { return probe.Measure(); }, epochs);
  const auto rows =
      static_cast<std::int64_t>(config.ensemble.member_subset_fraction * report.train_size);
  for (std::size_t b = 0; b < backends.size(); ++b) {
    nlohmann::ordered_json epoch =
        Figure("train", "dynamics_epoch", config, epoch_runs[b].seconds);
    epoch["backend"] = backends[b];
    epoch["training_backend"] = trainees[b]->training_backend();
    epoch["members"] = config.ensemble.ensemble_size;
    epoch["hidden"] = config.ensemble.hidden_sizes;
    epoch["transitions"] = args.transitions;
    epoch["rows_per_member"] = rows;
    epoch["batch_size"] = config.ensemble.batch_size;
    AddRate(epoch, 3.0 * trainees[b]->PredictFlops(rows), epoch_runs[b]);
    if (!batch_candidates.is_null()) {
      epoch["batch_product_candidates"] = batch_candidates;
      double best = 0.0;
      for (const auto& [name, value] : batch_candidates.items()) {
        if (value.is_number()) best = std::max(best, value.get<double>());
      }
      if (best > 0.0) epoch["ratio_to_batch_ceiling"] = epoch["gflops"].get<double>() / best;
    }
    emit(epoch);
  }
  if (device.is_cpu()) {
    nlohmann::ordered_json adam = AdamStepFigure(config, shape, args.runs);
    // One step per batch: the epoch's share of optimiser passes.
    const std::int64_t batches =
        (rows + config.ensemble.batch_size - 1) / config.ensemble.batch_size;
    adam["steps_per_epoch"] = batches;
    adam["epoch_ms"] = adam["median_ms"].get<double>() * static_cast<double>(batches);
    emit(adam);
  }

  if (args.full_fit) {
    EnsembleDynamics fitted(shape.state_dim, shape.action_dim, config.ensemble, args.seed);
    TimedRuns fit_run;
    fit_run.ceilings.push_back(probe.Measure());
    fit_run.seconds.push_back(SecondsOf([&] {
      report = fitted.Fit(data);
      Synchronize(device);
    }));
    nlohmann::ordered_json fit = Figure("train", "dynamics_fit", config, fit_run.seconds);
    fit["epochs"] = report.epochs;
    fit["max_epochs"] = config.ensemble.max_epochs;
    AddRate(fit, 3.0 * fitted.PredictFlops(rows) * report.epochs, fit_run);
    emit(fit);
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
  emit(line);
}

}  // namespace cmbrl::bench

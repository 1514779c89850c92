// cmbrl's Python module, the compiled half (`cmbrl._cmbrl`): environments, vectors of them,
// training and trained runs. python/cmbrl/__init__.py builds the Gymnasium-style surface on it.
// Every long call (stepping, planning, training) releases the GIL; cmbrl::Error becomes
// cmbrl.Error (a ValueError) with the same message.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <torch/torch.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/env_throughput.h"
#include "cmbrl/agent/mpc_agent.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/env/scene.h"
#include "cmbrl/env/vector_env.h"
#include "cmbrl/experiment/config.h"
#include "cmbrl/experiment/evaluation.h"
#include "cmbrl/experiment/loaded_run.h"
#include "cmbrl/experiment/trainer.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/transition_buffer.h"
#include "cmbrl/models/xgboost_cost_model.h"
#include "cmbrl/viz/scene_picture.h"

namespace py = pybind11;

namespace cmbrl::python {
namespace {

using Doubles = py::array_t<double, py::array::c_style>;

// A numpy array that owns `values` without copying them, shaped `shape`.
template <typename T>
py::array_t<T> Own(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), free);
}

py::array_t<double> Own(std::vector<double>&& values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  return Own<double>(std::move(values), {n});
}

// An action-like Python object as `count` doubles: any real-valued array of exactly `shape`.
std::vector<double> ActionValues(const py::handle& action, const std::vector<py::ssize_t>& shape,
                                 const char* what) {
  const py::array array = py::array::ensure(action);
  Require(static_cast<bool>(array), "{}: expected a numpy array or a sequence of numbers", what);
  const char kind = array.dtype().kind();
  Require(kind == 'f' || kind == 'i' || kind == 'u',
          "{} has dtype {}: expected real numbers (float or integer)", what,
          std::string(py::str(array.dtype())));
  std::vector<py::ssize_t> got(array.shape(), array.shape() + array.ndim());
  Require(got == shape, "{} has shape {}: expected {}", what,
          std::string(py::str(py::tuple(py::cast(got)))),
          std::string(py::str(py::tuple(py::cast(shape)))));
  const Doubles values = Doubles::ensure(array);
  return std::vector<double>(values.data(), values.data() + values.size());
}

py::dict BoxDict(const BoxSpec& box) {
  py::dict d;
  d["low"] = Own(std::vector<double>(box.low));
  d["high"] = Own(std::vector<double>(box.high));
  d["names"] = box.names;
  return d;
}

py::dict SceneDict(const SceneState& scene) {
  py::dict d;
  d["robot_name"] = scene.robot_name;
  d["robot_radius"] = scene.robot_radius;
  d["robot_position"] = Own({scene.robot.position.x, scene.robot.position.y});
  d["robot_yaw"] = scene.robot.yaw;
  d["goal"] = Own({scene.goal.x, scene.goal.y});
  d["goal_radius"] = scene.goal_radius;
  std::vector<double> hazards, vases;
  for (const Vec2& h : scene.hazards) hazards.insert(hazards.end(), {h.x, h.y});
  for (const Pose2& v : scene.vases) vases.insert(vases.end(), {v.position.x, v.position.y, v.yaw});
  d["hazards"] = Own<double>(std::move(hazards), {static_cast<py::ssize_t>(scene.hazards.size()), 2});
  d["hazard_radius"] = scene.hazard_radius;
  d["vases"] = Own<double>(std::move(vases), {static_cast<py::ssize_t>(scene.vases.size()), 3});
  d["vase_half_size"] = scene.vase_half_size;
  const Extents& p = scene.placement;
  d["placement"] = py::make_tuple(p.x_min, p.y_min, p.x_max, p.y_max);
  return d;
}

py::array_t<std::uint8_t> RgbArray(RgbImage&& image) {
  return Own<std::uint8_t>(std::move(image.pixels),
                           {image.geometry.height_px, image.geometry.width_px, 3});
}

// One environment, with the episode's path kept for render().
class PyEnv {
 public:
  PyEnv(const std::string& task, const std::string& variant, const std::string& spawn)
      : env_(MakeEnv(task, ParseVariant(variant), ParseSpawn(spawn))), task_(task) {}

  py::tuple Reset(std::optional<std::uint64_t> seed) {
    Open();
    std::vector<double> observation;
    {
      py::gil_scoped_release release;
      observation = env_->Reset(seed);
    }
    StartPath();
    return py::make_tuple(Own(std::move(observation)), py::dict());
  }

  py::tuple Step(const py::handle& action) {
    Open();
    Require(started_, "step() before reset(): reset the environment first");
    const std::vector<double> values = ActionValues(
        action, {static_cast<py::ssize_t>(env_->action_spec().size())}, "the action");
    StepResult step;
    {
      py::gil_scoped_release release;
      step = env_->Step(values);
    }
    if (const SceneSource* source = env_->scene_source()) {
      const SceneState scene = source->Scene();
      if (step.info.goal_met) reached_goals_.push_back(last_goal_);
      last_goal_ = scene.goal;
      path_.push_back(scene.robot.position);
      path_violations_.push_back(step.cost > 0);
    }
    py::dict info;
    info["goal_met"] = step.info.goal_met;
    info["cost_hazards"] = step.info.cost_hazards;
    info["cost_vases_contact"] = step.info.cost_vases_contact;
    info["cost_vases_velocity"] = step.info.cost_vases_velocity;
    info["env_steps"] = step.info.env_steps;
    info["physics_error"] = step.info.physics_error;
    return py::make_tuple(Own(std::move(step.observation)), step.reward, step.cost,
                          step.terminated, step.truncated, info);
  }

  py::dict GroundTruth() const {
    Open();
    const SceneSource* source = env_->scene_source();
    Require(source != nullptr, "{} has no ground truth to show", task_);
    return SceneDict(source->Scene());
  }

  py::array_t<std::uint8_t> Render(int size_px) const {
    Open();
    const SceneSource* source = env_->scene_source();
    Require(source != nullptr, "{} has no scene to render", task_);
    ScenePicture picture{source->Scene(), path_, path_violations_, reached_goals_, task_, {}};
    ScenePictureOptions options;
    options.size_px = size_px;
    RgbImage image;
    {
      py::gil_scoped_release release;
      image = DrawScenePictureRgb(picture, options);
    }
    return RgbArray(std::move(image));
  }

  // Writes the picture of render() as PNG, with a caption and the planner's predicted paths
  // (dicts of points (K, 2), feasible, chosen, as Agent.predictions gives them).
  void SavePicture(const std::string& path, int size_px, const std::string& caption,
                   const py::list& predictions) const {
    Open();
    const SceneSource* source = env_->scene_source();
    Require(source != nullptr, "{} has no scene to draw", task_);
    ScenePicture picture{source->Scene(), path_, path_violations_, reached_goals_,
                         caption.empty() ? task_ : caption, {}};
    for (const py::handle& item : predictions) {
      const py::dict d = py::reinterpret_borrow<py::dict>(item);
      const Doubles points = Doubles::ensure(d["points"]);
      Require(static_cast<bool>(points) && points.ndim() == 2 && points.shape(1) == 2,
              "a prediction's points: expected a (K, 2) array");
      PredictedPath predicted;
      for (py::ssize_t i = 0; i < points.shape(0); ++i) {
        predicted.points.push_back({points.at(i, 0), points.at(i, 1)});
      }
      predicted.feasible = d["feasible"].cast<bool>();
      predicted.chosen = d["chosen"].cast<bool>();
      picture.predictions.push_back(std::move(predicted));
    }
    ScenePictureOptions options;
    options.size_px = size_px;
    py::gil_scoped_release release;
    WriteScenePng(picture, path, options);
  }

  py::dict ObservationSpec() const { return BoxDict(env_->observation_spec()); }
  py::dict ActionSpec() const { return BoxDict(env_->action_spec()); }
  int max_episode_steps() const { return env_->max_episode_steps(); }
  double agent_step_seconds() const { return env_->agent_step_seconds(); }
  void Close() { closed_ = true; }
  bool closed() const { return closed_; }
  Env& env() { return *env_; }

 private:
  void Open() const { Require(!closed_, "the {} environment is closed", task_); }
  void StartPath() {
    started_ = true;
    path_.clear();
    path_violations_.clear();
    reached_goals_.clear();
    if (const SceneSource* source = env_->scene_source()) {
      const SceneState scene = source->Scene();
      path_.push_back(scene.robot.position);
      path_violations_.push_back(false);
      last_goal_ = scene.goal;
    }
  }

  std::unique_ptr<Env> env_;
  std::string task_;
  bool closed_ = false;
  bool started_ = false;
  std::vector<Vec2> path_;
  std::vector<bool> path_violations_;
  std::vector<Vec2> reached_goals_;
  Vec2 last_goal_;
};

class PyVectorEnv {
 public:
  PyVectorEnv(const std::string& task, int num_envs, const std::string& variant,
              const std::string& spawn, int threads)
      : task_(task) {
    Require(num_envs >= 1, "num_envs is {}: expected at least 1", num_envs);
    std::vector<std::unique_ptr<Env>> envs;
    for (int k = 0; k < num_envs; ++k) {
      envs.push_back(MakeEnv(task, ParseVariant(variant), ParseSpawn(spawn)));
    }
    vector_ = std::make_unique<VectorEnv>(std::move(envs), threads);
  }

  py::tuple Reset(std::optional<std::uint64_t> seed) {
    Open();
    std::vector<double> observations;
    {
      py::gil_scoped_release release;
      observations = vector_->Reset(seed);
    }
    started_ = true;
    return py::make_tuple(Own<double>(std::move(observations), {vector_->size(), Width()}),
                          py::dict());
  }

  py::tuple Step(const py::handle& actions) {
    Open();
    Require(started_, "step() before reset(): reset the environments first");
    const py::ssize_t n = vector_->size();
    const std::vector<double> values = ActionValues(
        actions, {n, static_cast<py::ssize_t>(vector_->env(0).action_spec().size())},
        "the actions");
    VectorStep step;
    {
      py::gil_scoped_release release;
      step = vector_->Step(values);
    }
    const auto flags = [n](const std::vector<std::uint8_t>& v) {
      py::array_t<bool> out(n);
      bool* data = out.mutable_data();
      for (py::ssize_t k = 0; k < n; ++k) data[k] = v[k] != 0;
      return out;
    };
    std::vector<std::uint8_t> ended(n);
    for (py::ssize_t k = 0; k < n; ++k) ended[k] = step.terminated[k] || step.truncated[k];
    py::dict info;
    info["goal_met"] = flags(step.goal_met);
    info["cost_hazards"] = Own(std::move(step.cost_hazards));
    info["cost_vases_contact"] = Own(std::move(step.cost_vases_contact));
    info["cost_vases_velocity"] = Own(std::move(step.cost_vases_velocity));
    info["final_observation"] = Own<double>(std::move(step.final_observations), {n, Width()});
    info["_final_observation"] = flags(ended);
    return py::make_tuple(Own<double>(std::move(step.observations), {n, Width()}),
                          Own(std::move(step.rewards)), Own(std::move(step.costs)),
                          flags(step.terminated), flags(step.truncated), info);
  }

  int size() const { return vector_->size(); }
  py::dict ObservationSpec() const { return BoxDict(vector_->env(0).observation_spec()); }
  py::dict ActionSpec() const { return BoxDict(vector_->env(0).action_spec()); }
  void Close() { closed_ = true; }
  bool closed() const { return closed_; }

 private:
  py::ssize_t Width() const { return vector_->env(0).observation_spec().size(); }
  void Open() const { Require(!closed_, "the vector of {} environments is closed", task_); }

  std::unique_ptr<VectorEnv> vector_;
  std::string task_;
  bool closed_ = false;
  bool started_ = false;
};

// Rows of a 2-D real array of `width` columns, as doubles; `what` names it in errors.
std::vector<double> Matrix(const py::handle& array, py::ssize_t rows, py::ssize_t width,
                           const char* what) {
  return ActionValues(array, {rows, width}, what);
}

py::ssize_t RowsOf(const py::handle& array, const char* what) {
  const py::array a = py::array::ensure(array);
  Require(static_cast<bool>(a) && a.ndim() == 2, "{}: expected a 2-D array (rows, columns)", what);
  return a.shape(0);
}

// A dynamics ensemble of its own, fitted on the caller's transitions (a ring of 500k, as in
// training: each fit adds the new ones and trains on all, warm-started after the first).
class PyEnsemble {
 public:
  PyEnsemble(int state_dim, int action_dim, int ensemble_size, const std::vector<int>& hidden,
             int max_epochs, std::uint64_t seed)
      : buffer_(state_dim, action_dim),
        dynamics_(state_dim, action_dim, Options(ensemble_size, hidden, max_epochs), seed) {}

  py::dict Fit(const py::handle& states, const py::handle& actions,
               const py::handle& next_states) {
    const py::ssize_t n = RowsOf(states, "states");
    const int s = dynamics_.state_dim(), a = dynamics_.action_dim();
    const std::vector<double> sv = Matrix(states, n, s, "states");
    const std::vector<double> av = Matrix(actions, n, a, "actions");
    const std::vector<double> nv = Matrix(next_states, n, s, "next_states");
    EnsembleFitReport report;
    {
      py::gil_scoped_release release;
      for (py::ssize_t i = 0; i < n; ++i) {
        buffer_.Add({sv.begin() + i * s, sv.begin() + (i + 1) * s},
                    {av.begin() + i * a, av.begin() + (i + 1) * a},
                    {nv.begin() + i * s, nv.begin() + (i + 1) * s});
      }
      report = dynamics_.Fit(buffer_);
    }
    py::dict d;
    d["epochs"] = report.epochs;
    d["train_size"] = report.train_size;
    d["validation_size"] = report.validation_size;
    d["train_mse"] = report.train_mse;
    d["validation_mse"] = report.validation_mse;
    d["stopped_early"] = report.stopped_early;
    d["seconds"] = report.seconds;
    return d;
  }

  // states (N, S), actions (N, A) -> every member's next state (E, N, S).
  py::array_t<double> Predict(const py::handle& states, const py::handle& actions) const {
    const py::ssize_t n = RowsOf(states, "states");
    return PredictNext(dynamics_, Matrix(states, n, dynamics_.state_dim(), "states"),
                       Matrix(actions, n, dynamics_.action_dim(), "actions"), n);
  }

  int transitions() const { return buffer_.size(); }

  static py::array_t<double> PredictNext(const EnsembleDynamics& dynamics,
                                         const std::vector<double>& states,
                                         const std::vector<double>& actions, py::ssize_t n) {
    const std::int64_t members = dynamics.ensemble_size();
    std::vector<double> out;
    {
      py::gil_scoped_release release;
      const torch::NoGradGuard no_grad;
      const auto rows = [&](const std::vector<double>& v, std::int64_t width) {
        return torch::tensor(v, torch::kDouble)
            .to(torch::kFloat)
            .view({1, n, width})
            .expand({members, n, width})
            .contiguous();
      };
      const torch::Tensor next =
          dynamics.Predict(rows(states, dynamics.state_dim()), rows(actions, dynamics.action_dim()))
              .to(torch::kCPU, torch::kDouble)
              .contiguous();
      out.assign(next.data_ptr<double>(), next.data_ptr<double>() + next.numel());
    }
    return Own<double>(std::move(out), {members, n, dynamics.state_dim()});
  }

 private:
  static EnsembleOptions Options(int ensemble_size, const std::vector<int>& hidden,
                                 int max_epochs) {
    EnsembleOptions o;
    o.ensemble_size = ensemble_size;
    o.hidden_sizes = hidden;
    o.max_epochs = max_epochs;
    return o;
  }

  TransitionBuffer buffer_;
  EnsembleDynamics dynamics_;
};

// A constraint classifier of its own, fitted from scratch on the caller's labelled states.
class PyCostClassifier {
 public:
  PyCostClassifier(int state_dim, int rounds, double threshold, std::uint64_t seed)
      : classifier_(state_dim, Options(rounds, threshold), seed) {}

  py::dict Fit(const py::handle& states, const py::handle& unsafe) {
    const int s = classifier_.state_dim();
    const py::ssize_t n = RowsOf(states, "states");
    const std::vector<double> sv = Matrix(states, n, s, "states");
    const std::vector<double> labels = ActionValues(unsafe, {n}, "unsafe");
    std::vector<float> safe_rows, unsafe_rows;
    for (py::ssize_t i = 0; i < n; ++i) {
      Require(labels[i] == 0 || labels[i] == 1, "unsafe[{}] is {}: expected 0 or 1", i, labels[i]);
      std::vector<float>& to = labels[i] != 0 ? unsafe_rows : safe_rows;
      to.insert(to.end(), sv.begin() + i * s, sv.begin() + (i + 1) * s);
    }
    CostFitReport report;
    {
      py::gil_scoped_release release;
      report = classifier_.FitArrays(safe_rows.data(), static_cast<int>(safe_rows.size() / s),
                                     unsafe_rows.data(), static_cast<int>(unsafe_rows.size() / s));
    }
    py::dict d;
    d["trained"] = report.trained;
    d["safe_used"] = report.safe_used;
    d["unsafe_used"] = report.unsafe_used;
    d["safe_accuracy"] = report.safe_accuracy;
    d["unsafe_accuracy"] = report.unsafe_accuracy;
    d["trees"] = report.trees;
    d["seconds"] = report.seconds;
    return d;
  }

  py::array Predict(const py::handle& states) const { return PredictViolation(classifier_, states); }

  static py::array PredictViolation(const XgbCostModel& classifier, const py::handle& states) {
    const py::ssize_t n = RowsOf(states, "states");
    const std::vector<double> sv = Matrix(states, n, classifier.state_dim(), "states");
    const std::vector<float> rows(sv.begin(), sv.end());
    std::vector<std::uint8_t> out;
    {
      py::gil_scoped_release release;
      out = classifier.PredictRows(rows.data(), static_cast<int>(n));
    }
    py::array_t<bool> verdict(n);
    for (py::ssize_t k = 0; k < n; ++k) verdict.mutable_data()[k] = out[k] != 0;
    return std::move(verdict);
  }

 private:
  static XgbCostModelOptions Options(int rounds, double threshold) {
    XgbCostModelOptions o;
    o.rounds = rounds;
    o.threshold = threshold;
    return o;
  }

  XgbCostModel classifier_;
};

// A trained run's agent.
class PyAgent {
 public:
  PyAgent(const std::string& run_dir, std::uint64_t seed) : run_(run_dir, seed) {}

  void BeginEpisode() { run_.policy().BeginEpisode(); }

  py::array_t<double> Act(const py::handle& observation) {
    const std::vector<double> values = ActionValues(
        observation, {static_cast<py::ssize_t>(run_.env().observation_spec().size())},
        "the observation");
    for (const double v : values) Require(std::isfinite(v), "the observation holds {}: expected finite values", v);
    std::vector<double> action;
    {
      py::gil_scoped_release release;
      action = run_.policy().Act(values);
    }
    return Own(std::move(action));
  }

  // The last plan in world coordinates: a list of dicts (points (H+1, 2), feasible, chosen).
  py::list Predictions(const py::dict& scene_of_plan, int samples) {
    SceneState scene;
    const auto xy = [](const py::handle& a) {
      const Doubles v = Doubles::ensure(a);
      Require(static_cast<bool>(v) && v.size() == 2, "expected a position of 2 numbers");
      return Vec2{v.data()[0], v.data()[1]};
    };
    scene.goal = xy(scene_of_plan["goal"]);
    scene.robot.position = xy(scene_of_plan["robot_position"]);
    std::vector<PredictedPath> paths;
    {
      py::gil_scoped_release release;
      paths = PlannerPredictions(run_.mpc_agent(), run_.env().observation_spec(), scene, samples);
    }
    py::list out;
    for (const PredictedPath& path : paths) {
      std::vector<double> points;
      for (const Vec2& p : path.points) points.insert(points.end(), {p.x, p.y});
      py::dict d;
      d["points"] = Own<double>(std::move(points), {static_cast<py::ssize_t>(path.points.size()), 2});
      d["feasible"] = path.feasible;
      d["chosen"] = path.chosen;
      out.append(d);
    }
    return out;
  }

  py::dict LastPlan() {
    MpcAgent& agent = run_.mpc_agent();
    py::dict d;
    d["milliseconds"] = agent.last_plan().milliseconds;
    d["iterations"] = agent.last_plan().iterations;
    d["feasible_fraction"] = agent.last_plan().feasible_fraction;
    d["infeasible_elite_fraction"] = agent.last_plan().infeasible_elite_fraction;
    const torch::Tensor sequence = agent.last_result().sequence.to(torch::kCPU, torch::kDouble).contiguous();
    d["actions"] = Own<double>(
        std::vector<double>(sequence.data_ptr<double>(), sequence.data_ptr<double>() + sequence.numel()),
        {sequence.size(0), sequence.size(1)});
    return d;
  }

  // Next states of every member: states (N, S), actions (N, A) -> (E, N, S).
  py::array_t<double> PredictNext(const py::handle& states, const py::handle& actions) {
    const EnsembleDynamics& dynamics = run_.dynamics();
    const py::ssize_t n = RowsOf(states, "states");
    return PyEnsemble::PredictNext(dynamics, Matrix(states, n, dynamics.state_dim(), "states"),
                                   Matrix(actions, n, dynamics.action_dim(), "actions"), n);
  }

  // The classifier's 0/1 violation prediction for states (N, S) -> (N) bool.
  py::array PredictViolation(const py::handle& states) {
    return PyCostClassifier::PredictViolation(run_.classifier(), states);
  }

  std::string ConfigYaml() const { return TrainConfigToYaml(run_.config()); }
  bool is_mpc() const { return run_.is_mpc(); }
  py::dict ObservationSpec() { return BoxDict(run_.env().observation_spec()); }
  py::dict ActionSpec() { return BoxDict(run_.env().action_spec()); }

 private:
  LoadedRun run_;
};

// Trains (or resumes) a run; `progress` sees each unit's summary, with the GIL held.
py::dict Train(const std::optional<std::string>& config_path,
               const std::optional<std::string>& config_text, const std::optional<std::string>& out,
               const std::optional<std::string>& resume, std::optional<std::int64_t> steps,
               std::optional<std::uint64_t> seed, const std::optional<std::string>& device,
               const std::function<void(py::dict)>& progress) {
  std::unique_ptr<Trainer> trainer;
  std::string run_dir;
  if (resume) {
    Require(!config_path && !config_text && !out && !seed && !device,
            "resume continues a run with its own config: give no config, out, seed or device "
            "with it (steps gives it a new budget)");
    run_dir = *resume;
    py::gil_scoped_release release;
    trainer = Trainer::Resume(run_dir, steps);
  } else {
    Require((config_path.has_value() != config_text.has_value()) && out.has_value(),
            "a new run needs a config (a YAML file or a dict) and out (the run directory)");
    const std::string source = config_path ? *config_path : "the config dict";
    TrainConfig config = config_path ? LoadTrainConfig(*config_path)
                                     : ParseTrainConfig(*config_text, source);
    if (steps) config.training.total_steps = *steps;
    if (seed) config.seed = *seed;
    if (device) SetTrainDevice(config, *device);
    ValidateTrainConfig(config, source);
    run_dir = *out;
    py::gil_scoped_release release;
    trainer = Trainer::Start(config, run_dir);
  }
  {
    py::gil_scoped_release release;
    trainer->Run([&](const ProgressSummary& unit) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C
      if (!progress) return;
      py::dict d;
      d["epoch"] = unit.epoch;
      d["steps"] = unit.steps;
      d["budget"] = unit.budget;
      d["episode_return"] = unit.episode_return;
      d["episode_cost"] = unit.episode_cost;
      d["seconds"] = unit.seconds;
      progress(d);  // a Python exception here stops training; the run resumes later
    });
  }
  py::dict summary;
  summary["run"] = run_dir;
  summary["steps"] = trainer->steps_done();
  summary["budget"] = trainer->learner().budget();
  return summary;
}

// `cmbrl bench env` for one task and variant, in this process: its JSON line.
std::string BenchEnv(const std::string& task, const std::string& variant, int steps, int runs,
                     std::uint64_t seed) {
  bench::EnvBenchOptions options;
  options.tasks = {task};
  options.variants = {variant};
  options.steps = steps;
  options.runs = runs;
  options.seed = seed;
  std::string line;
  py::gil_scoped_release release;
  bench::RunEnvBench(options, [&](const nlohmann::ordered_json& figure) { line = figure.dump(); });
  return line;
}

}  // namespace

PYBIND11_MODULE(_cmbrl, m) {
  m.doc() = "cmbrl's compiled core; use the cmbrl package";
  py::register_exception<Error>(m, "Error", PyExc_ValueError);
  m.def("env_names", &EnvNames, "the registered tasks");

  py::class_<PyEnv>(m, "Env")
      .def(py::init<const std::string&, const std::string&, const std::string&>(),
           py::arg("task"), py::arg("variant"), py::arg("spawn"))
      .def("reset", &PyEnv::Reset, py::arg("seed") = py::none())
      .def("step", &PyEnv::Step, py::arg("action"))
      .def("ground_truth", &PyEnv::GroundTruth)
      .def("render", &PyEnv::Render, py::arg("size_px"))
      .def("save_picture", &PyEnv::SavePicture, py::arg("path"), py::arg("size_px"),
           py::arg("caption"), py::arg("predictions"))
      .def("observation_spec", &PyEnv::ObservationSpec)
      .def("action_spec", &PyEnv::ActionSpec)
      .def_property_readonly("max_episode_steps", &PyEnv::max_episode_steps)
      .def_property_readonly("agent_step_seconds", &PyEnv::agent_step_seconds)
      .def_property_readonly("closed", &PyEnv::closed)
      .def("close", &PyEnv::Close);

  py::class_<PyVectorEnv>(m, "VectorEnv")
      .def(py::init<const std::string&, int, const std::string&, const std::string&, int>(),
           py::arg("task"), py::arg("num_envs"), py::arg("variant"), py::arg("spawn"),
           py::arg("threads"))
      .def("reset", &PyVectorEnv::Reset, py::arg("seed") = py::none())
      .def("step", &PyVectorEnv::Step, py::arg("actions"))
      .def("observation_spec", &PyVectorEnv::ObservationSpec)
      .def("action_spec", &PyVectorEnv::ActionSpec)
      .def_property_readonly("num_envs", &PyVectorEnv::size)
      .def_property_readonly("closed", &PyVectorEnv::closed)
      .def("close", &PyVectorEnv::Close);

  py::class_<PyEnsemble>(m, "Ensemble")
      .def(py::init<int, int, int, const std::vector<int>&, int, std::uint64_t>(),
           py::arg("state_dim"), py::arg("action_dim"), py::arg("ensemble_size"),
           py::arg("hidden_sizes"), py::arg("max_epochs"), py::arg("seed"))
      .def("fit", &PyEnsemble::Fit, py::arg("states"), py::arg("actions"), py::arg("next_states"))
      .def("predict", &PyEnsemble::Predict, py::arg("states"), py::arg("actions"))
      .def_property_readonly("transitions", &PyEnsemble::transitions);

  py::class_<PyCostClassifier>(m, "CostClassifier")
      .def(py::init<int, int, double, std::uint64_t>(), py::arg("state_dim"), py::arg("rounds"),
           py::arg("threshold"), py::arg("seed"))
      .def("fit", &PyCostClassifier::Fit, py::arg("states"), py::arg("unsafe"))
      .def("predict", &PyCostClassifier::Predict, py::arg("states"));

  py::class_<PyAgent>(m, "Agent")
      .def(py::init<const std::string&, std::uint64_t>(), py::arg("run_dir"), py::arg("seed"))
      .def("begin_episode", &PyAgent::BeginEpisode)
      .def("act", &PyAgent::Act, py::arg("observation"))
      .def("predictions", &PyAgent::Predictions, py::arg("scene"), py::arg("samples"))
      .def("last_plan", &PyAgent::LastPlan)
      .def("predict_next", &PyAgent::PredictNext, py::arg("states"), py::arg("actions"))
      .def("predict_violation", &PyAgent::PredictViolation, py::arg("states"))
      .def("config_yaml", &PyAgent::ConfigYaml)
      .def("observation_spec", &PyAgent::ObservationSpec)
      .def("action_spec", &PyAgent::ActionSpec)
      .def_property_readonly("is_mpc", &PyAgent::is_mpc);

  m.def("bench_env", &BenchEnv, py::arg("task"), py::arg("variant"), py::arg("steps"),
        py::arg("runs"), py::arg("seed"));
  m.def("train", &Train, py::arg("config_path"), py::arg("config_text"), py::arg("out"),
        py::arg("resume"), py::arg("steps"), py::arg("seed"), py::arg("device"),
        py::arg("progress"));
}

}  // namespace cmbrl::python

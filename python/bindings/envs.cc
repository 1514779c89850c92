// The environments in Python: one (Env, with the episode's path for pictures) and vectors of
// them (VectorEnv), plus `cmbrl bench env` in this process.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/env_throughput.h"
#include "cmbrl/core/binary_io.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/env/previous_action_env.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/env/tasks/task_spec.h"
#include "cmbrl/env/scene.h"
#include "cmbrl/env/vector_env.h"
#include "cmbrl/viz/scene_picture.h"
#include "python/bindings/arrays.h"
#include "python/bindings/bindings.h"

namespace cmbrl::python {
namespace {

py::dict SceneDict(const SceneState& scene) {
  py::dict d;
  d["robot_name"] = scene.robot_name;
  d["robot_radius"] = scene.robot_radius;
  d["robot_position"] = Own({scene.robot.position.x, scene.robot.position.y});
  d["robot_yaw"] = scene.robot.yaw;
  d["robot_upright"] = scene.robot_upright;
  d["goal"] = Own({scene.goal.x, scene.goal.y});
  d["goal_radius"] = scene.goal_radius;
  std::vector<double> hazards, vases;
  for (const Vec2& h : scene.hazards) hazards.insert(hazards.end(), {h.x, h.y});
  for (const Pose2& v : scene.vases) vases.insert(vases.end(), {v.position.x, v.position.y, v.yaw});
  d["hazards"] =
      Own<double>(std::move(hazards), {static_cast<py::ssize_t>(scene.hazards.size()), 2});
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

// One environment, with the episode's path kept for render(). Thread-safe: calls from several
// Python threads take turns (ObjectLock), the GIL released around the environment's own work.
class PyEnv {
 public:
  // previous_action: the observation ends with the action last run (PreviousActionEnv), as a
  // run with environment.previous_action observes it.
  PyEnv(const std::string& task, const std::string& variant, const std::string& spawn,
        bool previous_action)
      : env_(MakeEnv(task, ParseVariant(variant), ParseSpawn(spawn))), task_(task) {
    if (previous_action) env_ = std::make_unique<PreviousActionEnv>(std::move(env_));
  }

  py::tuple Reset(std::optional<std::uint64_t> seed) {
    const ObjectLock lock(mutex_);
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
    const ObjectLock lock(mutex_);
    Open();
    Require(started_, "step() before reset(): reset the environment first");
    const std::vector<double> values =
        RealValues(action, {static_cast<py::ssize_t>(env_->action_spec().size())}, "the action");
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
    info["cost_buttons"] = step.info.cost_buttons;
    info["cost_gremlins"] = step.info.cost_gremlins;
    info["cost_pillars"] = step.info.cost_pillars;
    info["cost_out_of_boundary"] = step.info.cost_out_of_boundary;
    info["cost_sum"] = CostSum(step.info);
    info["env_steps"] = step.info.env_steps;
    info["physics_error"] = step.info.physics_error;
    return py::make_tuple(Own(std::move(step.observation)), step.reward, step.cost, step.terminated,
                          step.truncated, info);
  }

  py::dict GroundTruth() const {
    const ObjectLock lock(mutex_);
    Open();
    const SceneSource* source = env_->scene_source();
    Require(source != nullptr, "{} has no ground truth to show", task_);
    return SceneDict(source->Scene());
  }

  py::array_t<std::uint8_t> Render(int size_px) const {
    const ObjectLock lock(mutex_);
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
    const ObjectLock lock(mutex_);
    Open();
    const SceneSource* source = env_->scene_source();
    Require(source != nullptr, "{} has no scene to draw", task_);
    ScenePicture picture{source->Scene(),
                         path_,
                         path_violations_,
                         reached_goals_,
                         caption.empty() ? task_ : caption,
                         {}};
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

  // The environment's whole state (Env::State) and the episode's path for pictures, as bytes
  // for pickle and deepcopy.
  py::bytes State() const {
    const ObjectLock lock(mutex_);
    Open();
    ByteWriter out;
    out.Write(env_->State());
    out.Write<std::uint8_t>(started_ ? 1 : 0);
    out.Write<std::uint64_t>(path_.size());
    for (size_t i = 0; i < path_.size(); ++i) {
      out.Write(path_[i]);
      out.Write<std::uint8_t>(path_violations_[i] ? 1 : 0);
    }
    out.Write<std::uint64_t>(reached_goals_.size());
    for (const Vec2& goal : reached_goals_) out.Write(goal);
    out.Write(last_goal_);
    return py::bytes(out.Take());
  }

  void SetState(const std::string& bytes) {
    const ObjectLock lock(mutex_);
    Open();
    ByteReader in(bytes, fmt::format("the pickled {} environment", task_));
    const std::string state = in.ReadString();
    const bool started = in.Read<std::uint8_t>() != 0;
    std::vector<Vec2> path, reached_goals;
    std::vector<bool> violations;
    for (auto count = in.Read<std::uint64_t>(); count > 0; --count) {
      path.push_back(in.Read<Vec2>());
      violations.push_back(in.Read<std::uint8_t>() != 0);
    }
    for (auto count = in.Read<std::uint64_t>(); count > 0; --count) {
      reached_goals.push_back(in.Read<Vec2>());
    }
    const Vec2 last_goal = in.Read<Vec2>();
    in.ExpectEnd();
    env_->SetState(state);  // checks its own part before changing anything
    started_ = started;
    path_ = std::move(path);
    path_violations_ = std::move(violations);
    reached_goals_ = std::move(reached_goals);
    last_goal_ = last_goal;
  }

  py::dict ObservationSpec() const { return BoxDict(env_->observation_spec()); }
  py::dict ActionSpec() const { return BoxDict(env_->action_spec()); }
  int max_episode_steps() const { return env_->max_episode_steps(); }
  double agent_step_seconds() const { return env_->agent_step_seconds(); }
  void Close() {
    const ObjectLock lock(mutex_);
    closed_ = true;
  }
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

  mutable std::mutex mutex_;  // ObjectLock: one call at a time
  std::unique_ptr<Env> env_;
  std::string task_;
  bool closed_ = false;
  bool started_ = false;
  std::vector<Vec2> path_;
  std::vector<bool> path_violations_;
  std::vector<Vec2> reached_goals_;
  Vec2 last_goal_;
};

// A VectorEnv of one task. Thread-safe: calls from several Python threads take turns.
class PyVectorEnv {
 public:
  PyVectorEnv(const std::string& task, int num_envs, const std::string& variant,
              const std::string& spawn, int threads, std::int64_t spin_us,
              const std::string& autoreset_mode, bool previous_action)
      : task_(task) {
    Require(autoreset_mode == "next-step" || autoreset_mode == "same-step" ||
                autoreset_mode == "disabled",
            "autoreset_mode is '{}': expected 'next-step', 'same-step' or 'disabled'",
            autoreset_mode);
    const Autoreset autoreset = autoreset_mode == "disabled"    ? Autoreset::kDisabled
                                : autoreset_mode == "same-step" ? Autoreset::kSameStep
                                                                : Autoreset::kNextStep;
    std::vector<std::unique_ptr<Env>> envs =
        MakeEnvs(task, ParseVariant(variant), ParseSpawn(spawn), num_envs);
    if (previous_action) {
      for (std::unique_ptr<Env>& env : envs) {
        env = std::make_unique<PreviousActionEnv>(std::move(env));
      }
    }
    // 0: one thread per core this process may use (VectorEnv keeps at most one per env).
    vector_ = std::make_unique<VectorEnv>(
        std::move(envs), threads == 0 ? CoreCount() : threads, std::chrono::microseconds(spin_us),
        autoreset);
    // Threads chosen for the caller: it measures whether they pay on this machine now.
    vector_->SetAdaptiveThreads(threads == 0);
  }

  // Gymnasium's reset_mask: resets environment k where mask[k], with seeds[k] when given.
  // Returns the (num_envs, obs) first observations, zero rows where not reset.
  py::array_t<double> ResetWhere(const std::vector<bool>& mask,
                                 const std::vector<std::uint64_t>& seeds) {
    const ObjectLock lock(mutex_);
    Open();
    const std::vector<std::uint8_t> flags(mask.begin(), mask.end());
    std::vector<double> observations;
    {
      py::gil_scoped_release release;
      observations = vector_->ResetWhere(flags, seeds);
    }
    started_ = true;
    return Own<double>(std::move(observations), {vector_->size(), Width()});
  }

  py::tuple Reset(std::optional<std::uint64_t> seed) {
    const ObjectLock lock(mutex_);
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
    const ObjectLock lock(mutex_);
    Open();
    Require(started_, "step() before reset(): reset the environments first");
    const py::ssize_t n = vector_->size();
    const std::vector<double> values =
        RealValues(actions, {n, static_cast<py::ssize_t>(vector_->env(0).action_spec().size())},
                   "the actions array");
    VectorStep step;
    {
      py::gil_scoped_release release;
      step = vector_->Step(values);
    }
    std::vector<std::uint8_t> ended(n);
    for (py::ssize_t k = 0; k < n; ++k) ended[k] = step.terminated[k] || step.truncated[k];
    py::dict info;
    info["goal_met"] = Flags(step.goal_met);
    info["cost_hazards"] = Own(std::move(step.cost_hazards));
    info["cost_vases_contact"] = Own(std::move(step.cost_vases_contact));
    info["cost_vases_velocity"] = Own(std::move(step.cost_vases_velocity));
    info["cost_buttons"] = Own(std::move(step.cost_buttons));
    info["cost_gremlins"] = Own(std::move(step.cost_gremlins));
    info["cost_pillars"] = Own(std::move(step.cost_pillars));
    info["cost_out_of_boundary"] = Own(std::move(step.cost_out_of_boundary));
    info["cost_sum"] = Own(std::move(step.cost_sums));
    // Gymnasium's masks: which environments' info has each key. An environment reset by this
    // step (next-step autoreset) has its reset's info, which has none of them.
    std::vector<std::uint8_t> stepped(n);
    for (py::ssize_t k = 0; k < n; ++k) stepped[k] = step.reset[k] == 0;
    std::vector<std::string> keys;
    for (const auto& [key, value] : info) keys.push_back(py::cast<std::string>(key));
    for (const std::string& key : keys) info[py::str("_" + key)] = Flags(stepped);
    if (vector_->autoreset() == Autoreset::kSameStep) {  // with the other modes the observation is the last one itself
      // Gymnasium 1.x's same-step names: the ended episodes' last observations and the info of
      // their last step (this step's, as the reset adds none), each with its mask.
      py::dict final_info;
      for (const auto& [key, value] : info) final_info[key] = value;
      info["final_obs"] = Own<double>(std::move(step.final_observations), {n, Width()});
      info["_final_obs"] = Flags(ended);
      info["final_info"] = final_info;
      info["_final_info"] = Flags(ended);
    }
    return py::make_tuple(Own<double>(std::move(step.observations), {n, Width()}),
                          Own(std::move(step.rewards)), Own(std::move(step.costs)),
                          Flags(step.terminated), Flags(step.truncated), info);
  }

  int size() const { return vector_->size(); }
  py::dict ObservationSpec() const { return BoxDict(vector_->env(0).observation_spec()); }
  py::dict ActionSpec() const { return BoxDict(vector_->env(0).action_spec()); }
  void Close() {
    const ObjectLock lock(mutex_);
    closed_ = true;
  }
  bool closed() const { return closed_; }

 private:
  py::ssize_t Width() const { return vector_->env(0).observation_spec().size(); }
  void Open() const { Require(!closed_, "the vector of {} environments is closed", task_); }

  mutable std::mutex mutex_;  // ObjectLock: one call at a time
  std::unique_ptr<VectorEnv> vector_;
  std::string task_;
  bool closed_ = false;
  bool started_ = false;
};

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

void BindEnvs(py::module_& m) {
  m.def("env_names", &EnvNames, "the registered tasks");
  m.def(
      "default_variant",
      [](const std::string& task) { return VariantName(DefaultVariant(FindTask(task))); },
      py::arg("task"), "the variant a task is made in when none is named");
  m.def(
      "episode_steps",
      [](const std::string& task, const std::string& variant) {
        const NavigationTaskSpec spec = NavigationTaskSpecByName(task, ParseVariant(variant));
        return (spec.max_env_steps + spec.action_repeat - 1) / spec.action_repeat;
      },
      py::arg("task"), py::arg("variant"), "agent steps in an episode of a task and variant");
  py::class_<PyEnv>(m, "Env")
      .def(py::init<const std::string&, const std::string&, const std::string&, bool>(),
           py::arg("task"), py::arg("variant"), py::arg("spawn"), py::arg("previous_action"))
      .def("reset", &PyEnv::Reset, py::arg("seed") = py::none())
      .def("step", &PyEnv::Step, py::arg("action"))
      .def("ground_truth", &PyEnv::GroundTruth)
      .def("state", &PyEnv::State)
      .def("set_state", &PyEnv::SetState, py::arg("state"))
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
      .def(py::init<const std::string&, int, const std::string&, const std::string&, int,
                    std::int64_t, const std::string&, bool>(),
           py::arg("task"), py::arg("num_envs"), py::arg("variant"), py::arg("spawn"),
           py::arg("threads"), py::arg("spin_us"), py::arg("autoreset_mode"),
           py::arg("previous_action"))
      .def("reset", &PyVectorEnv::Reset, py::arg("seed") = py::none())
      .def("reset_where", &PyVectorEnv::ResetWhere, py::arg("mask"), py::arg("seeds"))
      .def("step", &PyVectorEnv::Step, py::arg("actions"))
      .def("observation_spec", &PyVectorEnv::ObservationSpec)
      .def("action_spec", &PyVectorEnv::ActionSpec)
      .def_property_readonly("num_envs", &PyVectorEnv::size)
      .def_property_readonly("closed", &PyVectorEnv::closed)
      .def("close", &PyVectorEnv::Close);

  m.def("bench_env", &BenchEnv, py::arg("task"), py::arg("variant"), py::arg("steps"),
        py::arg("runs"), py::arg("seed"));
}

}  // namespace cmbrl::python

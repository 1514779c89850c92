// Training and trained runs in Python: train (or resume) a run as `cmbrl train` does, and a
// run's agent (LoadedRun) acting on numpy observations, with its last plan and its models.
#include <fmt/ranges.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/eval/evaluation.h"
#include "cmbrl/eval/loaded_run.h"
#include "cmbrl/eval/rollout.h"
#include "cmbrl/learners/mpc/mpc_agent.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/planning/reward_term.h"
#include "cmbrl/run/run_directory.h"
#include "cmbrl/train/trainer.h"
#include "python/bindings/arrays.h"
#include "python/bindings/bindings.h"
#include "python/bindings/python_env.h"
#include "python/bindings/python_inputs.h"

namespace cmbrl::python {
namespace {

// A run's objective and the functions given must agree: a function where the objective names
// python, none otherwise; and an environment given from Python must be the one the run's task
// names.
void CheckFunctionsGiven(const TrainConfig& config, bool reward, bool termination,
                         const std::string& run,
                         const std::optional<GivenEnv>& env = std::nullopt) {
  if (env) {  // a declared one is named by what makes it, whatever the task is called
    const std::string made =
        config.python.env.empty() ? config.task : DeclaredEnvTask(config.python.env);
    Require(made == env->task(),
            "{} was trained on task '{}': the environment given is '{}' (give the one it was "
            "trained on)",
            run, made, env->task());
  }
  Require(!reward || config.objective.reward == "python",
          "{} plans with objective.reward '{}': give no reward function", run,
          config.objective.reward);
  Require(!termination || config.objective.termination == "python",
          "{} plans with objective.termination '{}': give no termination function", run,
          config.objective.termination);
}

// The environment given from Python, where a factory is.
std::optional<GivenEnv> GivenEnvOf(const std::optional<py::function>& factory,
                                   const std::optional<std::string>& name) {
  if (!factory) return std::nullopt;
  return GivenEnv(*factory, name.value_or("environment"));
}

// CheckFunctionsGiven against the run in `run_dir`, before it is loaded (a folder without a run
// is left to the loader to name). Returns true, so that a member initialiser can run it first.
bool CheckRunGiven(const std::string& run_dir, bool reward, bool termination,
                   const std::optional<GivenEnv>& env) {
  const RunDirectory run(run_dir);
  if (!run.HoldsRun()) return true;
  CheckFunctionsGiven(LoadTrainConfig(run.config_file().string()), reward, termination,
                      fmt::format("run '{}'", run_dir), env);
  return true;
}

// A trained run's agent (LoadedRun). Thread-safe: calls from several Python threads take turns
// (ObjectLock), as its planner, models and environment are one state.
class PyAgent {
 public:
  PyAgent(const std::string& run_dir, std::uint64_t seed, const std::vector<std::string>& overrides,
          const std::optional<py::function>& reward, const std::optional<py::function>& termination,
          const std::optional<GivenEnv>& env)
      : given_checked_(CheckRunGiven(run_dir, reward.has_value(), termination.has_value(), env)),
        run_(run_dir, seed, overrides, InputsWith(reward, termination, env)) {
    python_env_ = dynamic_cast<const PythonEnv*>(&run_.env());
  }

  void BeginEpisode() {
    const ObjectLock lock(mutex_);
    plan_paths_.reset();
    run_.policy().BeginEpisode();
  }

  py::array_t<double> Act(const py::handle& observation) {
    const ObjectLock lock(mutex_);
    const std::vector<double> values =
        RealValues(observation, {static_cast<py::ssize_t>(run_.env().observation_spec().size())},
                   "the observation");
    for (const double v : values)
      Require(std::isfinite(v), "the observation holds {}: expected finite values", v);
    std::vector<double> action;
    plan_paths_.reset();  // a new plan
    paths_lost_ = false;
    {
      py::gil_scoped_release release;
      action = run_.policy().Act(values);
    }
    // A Python environment's own action (cmbrl plans in [-1, 1] per component).
    if (python_env_ != nullptr) action = python_env_->EnvAction(action);
    return Own(std::move(action));
  }

  // The last plan in world coordinates: a list of dicts (points (H+1, 2), feasible, chosen,
  // member), `samples` sampled sequences times the members, then the executed plan's. The paths
  // are taken once per plan (taking them re-rolls the executed plan through the objective), so
  // every call after one act() selects from the same plan, placed in the first call's scene.
  py::list Predictions(const py::dict& scene_of_plan, int samples) {
    const ObjectLock lock(mutex_);
    RequirePlan("predictions");
    Require(plan_paths_.has_value() || !paths_lost_,
            "predictions() after score(): scoring replaced the plan's predicted paths; call "
            "predictions() before score(), or act() again");
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
      if (!plan_paths_) {
        plan_paths_ = TakePlanPaths(run_.mpc_agent(), run_.env().observation_spec(), scene);
      }
      paths = SelectPredictions(*plan_paths_, samples);
    }
    py::list out;
    const size_t members = static_cast<size_t>(std::max(1, plan_paths_->members));
    for (size_t index = 0; index < paths.size(); ++index) {
      const PredictedPath& path = paths[index];
      std::vector<double> points;
      for (const Vec2& p : path.points) points.insert(points.end(), {p.x, p.y});
      py::dict d;
      d["points"] =
          Own<double>(std::move(points), {static_cast<py::ssize_t>(path.points.size()), 2});
      d["feasible"] = path.feasible;
      d["chosen"] = path.chosen;
      d["member"] = static_cast<int>(index % members);
      out.append(d);
    }
    return out;
  }

  py::dict LastPlan() {
    const ObjectLock lock(mutex_);
    RequirePlan("last_plan");
    MpcAgent& agent = run_.mpc_agent();
    using P = std::decay_t<decltype(agent.last_plan())>;
    py::dict d = AsDict(agent.last_plan(), Field("milliseconds", &P::milliseconds),
                        Field("iterations", &P::iterations),
                        Field("feasible_fraction", &P::feasible_fraction),
                        Field("infeasible_elite_fraction", &P::infeasible_elite_fraction));
    const torch::Tensor& sequence = agent.last_result().sequence;
    d["actions"] = Own<double>(ToDoubles(sequence), {sequence.size(0), sequence.size(1)});
    return d;
  }

  // Next states of every member: states (N, S), actions (N, A) -> (E, N, S).
  py::array_t<double> PredictNext(const py::handle& states, const py::handle& actions) {
    const ObjectLock lock(mutex_);
    const DynamicsModel& dynamics = run_.planning_dynamics();
    const py::ssize_t n = RowsOf(states, "states");
    return PredictNextStates(dynamics, Matrix(states, n, dynamics.state_dim(), "states"),
                             Matrix(actions, n, dynamics.action_dim(), "actions"), n);
  }

  // The objective's scores of action sequences (N, H, A) from one observation: a dict of
  // reward_cost and constraint_cost (N) and feasible (N) bool.
  py::dict Score(const py::handle& observation, const py::handle& sequences) {
    const ObjectLock lock(mutex_);
    MpcAgent& agent = run_.mpc_agent();
    const std::vector<double> state = RealValues(
        observation, {static_cast<py::ssize_t>(run_.dynamics().state_dim())}, "the observation");
    const py::array array = py::array::ensure(sequences);
    const py::ssize_t horizon = agent.horizon(), width = run_.dynamics().action_dim();
    Require(static_cast<bool>(array) && array.ndim() == 3,
            "sequences: expected a 3-D array (N, {}, {}): N action sequences of the planner's "
            "horizon",
            horizon, width);
    const py::ssize_t n = array.shape(0);
    const std::vector<double> values = RealValues(array, {n, horizon, width}, "the sequences");
    // The objective's last trajectories become these sequences': the plan's paths, unless
    // already taken, cannot be taken after this.
    if (!plan_paths_) paths_lost_ = true;
    std::vector<double> reward, constraint;
    {
      py::gil_scoped_release release;
      const ObjectiveValues scores =
          agent.Score(state, torch::tensor(values, torch::kDouble).view({n, horizon, width}));
      reward = ToDoubles(scores.reward_cost);
      constraint = ToDoubles(scores.constraint_cost);
    }
    py::array_t<bool> feasible(n);
    for (py::ssize_t i = 0; i < n; ++i) {
      feasible.mutable_at(i) = constraint[static_cast<size_t>(i)] == 0.0;
    }
    py::dict d;
    d["reward_cost"] = Own(std::move(reward));
    d["constraint_cost"] = Own(std::move(constraint));
    d["feasible"] = feasible;
    return d;
  }

  // The classifier's 0/1 violation prediction for states (N, S) -> (N) bool.
  py::array PredictViolation(const py::handle& states) {
    const ObjectLock lock(mutex_);
    return PredictViolations(run_.classifier(), states);
  }

  std::string ConfigYaml() const { return TrainConfigToYaml(run_.config()); }
  // The environment the run was trained in: task, variant, spawn and whether it observes the
  // previous action, as cmbrl.Env takes them.
  py::dict Environment() const {
    py::dict d;
    d["task"] = run_.config().task;
    d["variant"] = VariantName(run_.config().variant);
    d["spawn"] = SpawnName(run_.config().spawn);
    d["previous_action"] = run_.config().previous_action;
    return d;
  }
  bool is_mpc() const { return run_.is_mpc(); }
  py::dict ObservationSpec() { return BoxDict(run_.env().observation_spec()); }
  py::dict ActionSpec() {
    return BoxDict(python_env_ != nullptr ? python_env_->EnvActionSpec()
                                          : run_.env().action_spec());
  }

 private:
  // A plan exists once act() has run (the MPC agent's planner has a result to read).
  void RequirePlan(const char* call) {
    const torch::Tensor& sequence = run_.mpc_agent().last_result().sequence;
    Require(sequence.defined() && sequence.numel() > 0,
            "{}() before act(): the agent has made no plan yet; call act(observation) first", call);
  }

  mutable std::mutex mutex_;  // ObjectLock: one call at a time
  bool given_checked_;        // what the run was trained with against what is given, before loading
  LoadedRun run_;
  const PythonEnv* python_env_ = nullptr;  // the run's env where it was given from Python
  std::optional<PlanPaths> plan_paths_;    // the last plan's paths, once predictions() took them
  bool paths_lost_ = false;                // score() ran after the plan, before they were taken
};

// Trains (or resumes) a run; `progress` sees each unit's summary, with the GIL held.
py::dict Train(const std::optional<std::vector<std::string>>& config_path,
               const std::optional<std::string>& config_text, const std::optional<std::string>& out,
               const std::optional<std::string>& resume, std::optional<std::int64_t> steps,
               std::optional<std::uint64_t> seed, const std::optional<std::string>& device,
               const std::function<void(py::dict)>& progress, double checkpoint_seconds,
               const std::optional<py::function>& reward,
               const std::optional<py::function>& termination,
               const std::optional<py::function>& env_factory,
               const std::optional<std::string>& env_name) {
  const std::optional<GivenEnv> env = GivenEnvOf(env_factory, env_name);
  const LearnerInputs inputs = InputsWith(reward, termination, env);
  std::unique_ptr<Trainer> trainer;
  std::string run_dir;
  if (resume) {
    Require(!config_path && !config_text && !out && !seed && !device,
            "resume continues a run with its own config: give no config, out, seed or device "
            "with it (steps gives it a new budget)");
    run_dir = *resume;
    CheckRunGiven(run_dir, reward.has_value(), termination.has_value(), env);
    py::gil_scoped_release release;
    trainer = Trainer::Resume(run_dir, steps, inputs);
  } else {
    Require((config_path.has_value() != config_text.has_value()) && out.has_value(),
            "a new run needs a config (a YAML file or a dict) and out (the run directory)");
    const std::string source =
        config_path ? fmt::format("{}", fmt::join(*config_path, "' + '")) : "the config dict";
    TrainConfig config =
        config_path ? LoadTrainConfig(*config_path) : ParseTrainConfig(*config_text, source);
    if (steps) config.training.total_steps = *steps;
    if (seed) config.seed = *seed;
    if (device) SetTrainDevice(config, *device);
    // Recorded in the run's config.yaml.
    // A function given plans with it (the run's config.yaml says so), unless the config asks
    // for another source by name.
    if (reward) {
      Require(config.objective.reward == "analytic" || config.objective.reward == "python",
              "{} asks for objective.reward '{}': give no reward function, or ask for 'python'",
              source, config.objective.reward);
      config.objective.reward = "python";
    }
    if (termination) {
      Require(config.objective.termination == "none" || config.objective.termination == "python",
              "{} asks for objective.termination '{}': give no termination function, or ask for "
              "'python'",
              source, config.objective.termination);
      config.objective.termination = "python";
    }
    RecordPythonEnv(config, inputs);  // the task is the environment given, its sizes recorded
    ValidateTrainConfig(config, source);
    run_dir = *out;
    py::gil_scoped_release release;
    trainer = Trainer::Start(config, run_dir, inputs);
  }
  // Ctrl-C is looked for after an agent step at most every 0.1 s (taking the GIL every step
  // would make a training thread wait on busy Python threads): the run stops at a checkpoint
  // taken then, and the KeyboardInterrupt it set is raised once training has let go of the run.
  bool interrupted = false;
  using Clock = std::chrono::steady_clock;
  Clock::time_point last_look = Clock::now();
  RunOptions options;
  options.checkpoint_seconds = checkpoint_seconds;
  options.stop_requested = [&] {
    if (interrupted || Clock::now() - last_look < std::chrono::milliseconds(100)) {
      return interrupted;
    }
    py::gil_scoped_acquire acquire;
    interrupted = PyErr_CheckSignals() != 0;
    last_look = Clock::now();
    return interrupted;
  };
  {
    py::gil_scoped_release release;
    options.on_unit = [&](const ProgressSummary& unit) {
      py::gil_scoped_acquire acquire;
      if (interrupted || !progress) return;
      py::dict d;
      d["epoch"] = unit.epoch;
      d["steps"] = unit.steps;
      d["budget"] = unit.budget;
      d["episode_return"] = unit.episode_return;
      d["episode_cost"] = unit.episode_cost;
      d["episodes"] = unit.episodes;
      d["seconds"] = unit.seconds;
      progress(d);  // a Python exception here stops training; the run resumes later
    };
    trainer->Run(options);
  }
  if (interrupted) throw py::error_already_set();
  py::dict summary;
  summary["run"] = run_dir;
  summary["steps"] = trainer->checkpointed_steps();
  summary["budget"] = trainer->learner().budget();
  // `cmbrl train`'s closing line's figures
  const SessionSummary session = trainer->ThisSession();
  summary["episodes_this_session"] = session.episodes;
  summary["cost_this_session"] = session.cost;
  py::dict split;
  for (const auto& [part, seconds] : session.seconds) split[py::str(part)] = seconds;
  summary["seconds_this_session"] = split;
  summary["cpu_seconds_this_session"] = session.cpu_seconds;
  return summary;
}

// Episodes of a trained run's agent (cmbrl eval's), as dicts of their sums and counts.
py::list Evaluate(const std::string& run_dir, int episodes, std::uint64_t seed,
                  bool reseed_each_episode, const std::vector<std::string>& overrides,
                  const std::optional<py::function>& reward,
                  const std::optional<py::function>& termination,
                  const std::optional<py::function>& env_factory,
                  const std::optional<std::string>& env_name,
                  const std::optional<std::string>& render) {
  const std::optional<GivenEnv> env = GivenEnvOf(env_factory, env_name);
  CheckRunGiven(run_dir, reward.has_value(), termination.has_value(), env);
  EvaluationOptions options;
  options.episodes = episodes;
  options.seed = seed;
  options.reseed_each_episode = reseed_each_episode;
  options.overrides = overrides;
  // Pictures as `cmbrl eval --render` draws them; without, no plans are recorded.
  if (!render) options.predictions_every = 0;
  if (render) options.frame_every = kFrameEvery;
  const LearnerInputs inputs = InputsWith(reward, termination, env);
  std::vector<EvaluatedEpisode> results;
  {
    py::gil_scoped_release release;
    results = EvaluateRun(run_dir, options, inputs);
  }
  const std::vector<std::string> pictures =
      render ? WriteEpisodePictures(results, *render) : std::vector<std::string>();
  py::list out;
  for (const EvaluatedEpisode& episode : results) {
    const EpisodeRecord& r = episode.record;
    py::dict d =
        AsDict(r, Field("return", &EpisodeRecord::episode_return),
               Field("cost", &EpisodeRecord::episode_cost), Field("steps", &EpisodeRecord::steps),
               Field("terminated", &EpisodeRecord::terminated),
               Field("truncated", &EpisodeRecord::truncated));
    for (const NamedFigure& figure : NavigationFigures(r)) {
      std::visit([&](auto value) { d[figure.name] = value; }, figure.value);
    }
    d["ms_per_plan"] = episode.mean_ms_per_plan;
    if (episode.mean_feasible_fraction) {
      d["feasible_fraction"] = *episode.mean_feasible_fraction;
      d["fallback_steps"] = *episode.fallback_step_fraction;
    }
    if (!pictures.empty()) d["picture"] = pictures[out.size()];
    out.append(d);
  }
  return out;
}

// Seconds that `steps` steps of a Python environment take through PythonEnv from C++ (the GIL
// released between them, as a learner steps it), resets included; the actions are drawn
// beforehand in [-1, 1].
double BenchPythonEnvSteps(const py::object& env, int steps, std::uint64_t seed) {
  Require(steps >= 1, "steps is {}: expected at least 1", steps);
  PythonEnv adapter(env, "bench");
  at::Generator generator = MakeCpuGenerator(seed);
  const torch::Tensor drawn =
      torch::rand({steps, adapter.action_spec().size()}, generator, torch::kDouble) * 2 - 1;
  std::vector<std::vector<double>> actions(steps);
  for (int t = 0; t < steps; ++t) {
    actions[t].assign(drawn[t].data_ptr<double>(), drawn[t].data_ptr<double>() + drawn.size(1));
  }
  py::gil_scoped_release release;
  adapter.Reset(seed);
  const auto start = std::chrono::steady_clock::now();
  for (int t = 0; t < steps; ++t) {
    const StepResult step = adapter.Step(actions[t]);
    if (step.terminated || step.truncated) adapter.Reset(std::nullopt);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Seconds of one planner iteration's call of a Python reward through its term (float32 tensors
// to float64 arrays and back) on `rows` predicted steps of random states and actions: the
// median of 5 calls after a first one (a planner calls it at every iteration).
double BenchPythonRewardCall(const py::function& reward, int rows, int state_dim, int action_dim,
                             std::uint64_t seed) {
  Require(rows >= 1 && state_dim >= 1 && action_dim >= 1,
          "rows, state_dim and action_dim are {}, {} and {}: expected at least 1 each", rows,
          state_dim, action_dim);
  // The term a run plans with (InputsWith's).
  const std::unique_ptr<RewardTerm> term = InputsWith(reward, std::nullopt).python_reward();
  at::Generator generator = MakeCpuGenerator(seed);
  const torch::Tensor states = torch::randn({rows, state_dim}, generator);
  const torch::Tensor actions = torch::rand({rows, action_dim}, generator);
  const torch::Tensor next_states = torch::randn({rows, state_dim}, generator);
  py::gil_scoped_release release;
  std::vector<double> seconds;
  for (int call = 0; call < 6; ++call) {
    const auto start = std::chrono::steady_clock::now();
    const torch::Tensor cost = term->Cost(states, actions, next_states);
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    Require(cost.numel() == rows, "the reward gave {} values for {} rows", cost.numel(), rows);
  }
  std::sort(seconds.begin() + 1, seconds.end());
  return seconds[3];
}

}  // namespace

void BindRuns(py::module_& m) {
  py::class_<PyAgent>(m, "Agent")
      .def(py::init([](const std::string& run_dir, std::uint64_t seed,
                       const std::vector<std::string>& overrides,
                       const std::optional<py::function>& reward,
                       const std::optional<py::function>& termination,
                       const std::optional<py::function>& env_factory,
                       const std::optional<std::string>& env_name) {
             return std::make_unique<PyAgent>(run_dir, seed, overrides, reward, termination,
                                              GivenEnvOf(env_factory, env_name));
           }),
           py::arg("run_dir"), py::arg("seed"), py::arg("overrides"), py::arg("reward"),
           py::arg("termination"), py::arg("env_factory"), py::arg("env_name"))
      .def("begin_episode", &PyAgent::BeginEpisode)
      .def("act", &PyAgent::Act, py::arg("observation"))
      .def("predictions", &PyAgent::Predictions, py::arg("scene"), py::arg("samples"))
      .def("last_plan", &PyAgent::LastPlan)
      .def("predict_next", &PyAgent::PredictNext, py::arg("states"), py::arg("actions"))
      .def("score", &PyAgent::Score, py::arg("observation"), py::arg("sequences"))
      .def("predict_violation", &PyAgent::PredictViolation, py::arg("states"))
      .def("config_yaml", &PyAgent::ConfigYaml)
      .def("environment", &PyAgent::Environment)
      .def("observation_spec", &PyAgent::ObservationSpec)
      .def("action_spec", &PyAgent::ActionSpec)
      .def_property_readonly("is_mpc", &PyAgent::is_mpc);

  m.def("evaluate", &Evaluate, py::arg("run_dir"), py::arg("episodes"), py::arg("seed"),
        py::arg("reseed_each_episode"), py::arg("overrides"), py::arg("reward"),
        py::arg("termination"), py::arg("env_factory"), py::arg("env_name"),
        py::arg("render") = std::nullopt);
  m.def("bench_python_env_steps", &BenchPythonEnvSteps, py::arg("env"), py::arg("steps"),
        py::arg("seed"));
  m.def("bench_python_reward_call", &BenchPythonRewardCall, py::arg("reward"), py::arg("rows"),
        py::arg("state_dim"), py::arg("action_dim"), py::arg("seed"));
  m.def("train", &Train, py::arg("config_path"), py::arg("config_text"), py::arg("out"),
        py::arg("resume"), py::arg("steps"), py::arg("seed"), py::arg("device"),
        py::arg("progress"), py::arg("checkpoint_seconds"), py::arg("reward"),
        py::arg("termination"), py::arg("env_factory"), py::arg("env_name"));
}

}  // namespace cmbrl::python

#include "python/bindings/python_env.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>

#include <cmath>
#include <utility>

#include "cmbrl/core/check.h"
#include "python/bindings/arrays.h"

namespace cmbrl::python {
namespace {

constexpr const char* kPickledPrefix = "pickle-base64:";

// A space's bounds, checked to be a 1-D Box of reals; `role` names it in errors.
BoxSpec BoxOf(const py::handle& space, const char* role, const std::string& env) {
  const std::string type = py::str(py::type::of(space).attr("__name__"));
  // gymnasium.spaces.Box, or cmbrl's look-alike (_Box) where gymnasium is not installed.
  const bool is_box = type.size() >= 3 && type.compare(type.size() - 3, 3, "Box") == 0;
  Require(is_box && py::hasattr(space, "low") && py::hasattr(space, "high"),
          "the environment {}'s {} is {}: cmbrl learns and plans on a 1-D Box of reals (wrap it, "
          "e.g. with gymnasium.wrappers.FlattenObservation)",
          env, role, std::string(py::repr(space)));
  const py::array low = py::array::ensure(space.attr("low"));
  const py::array high = py::array::ensure(space.attr("high"));
  Require(low && high && low.ndim() == 1 && high.ndim() == 1 && low.shape(0) == high.shape(0) &&
              low.shape(0) >= 1,
          "the environment {}'s {} is {}: expected a 1-D Box with at least one component", env,
          role, std::string(py::repr(space)));
  const char kind = low.dtype().kind();
  Require(kind == 'f' || kind == 'i' || kind == 'u',
          "the environment {}'s {} has dtype {}: expected real numbers", env, role,
          std::string(py::str(low.dtype())));
  BoxSpec box;
  const auto n = static_cast<py::ssize_t>(low.shape(0));
  box.low = RealValues(low, {n}, role);
  box.high = RealValues(high, {n}, role);
  const std::string prefix = std::string(role) == "action_space" ? "action" : "observation";
  for (py::ssize_t i = 0; i < n; ++i) box.names.push_back(fmt::format("{}_{}", prefix, i));
  return box;
}

}  // namespace

PythonEnv::PythonEnv(py::object env, std::string name)
    : env_(std::move(env)), name_(std::move(name)) {
  observation_spec_ = BoxOf(env_.attr("observation_space"), "observation_space", name_);
  const BoxSpec actions = BoxOf(env_.attr("action_space"), "action_space", name_);
  env_low_ = actions.low;
  env_high_ = actions.high;
  identity_actions_ = true;
  for (int i = 0; i < actions.size(); ++i) {
    Require(std::isfinite(env_low_[i]) && std::isfinite(env_high_[i]) && env_low_[i] < env_high_[i],
            "the environment {}'s action_space bounds component {} to [{}, {}]: cmbrl samples "
            "actions in a finite box (expected finite low < high)",
            name_, i, env_low_[i], env_high_[i]);
    identity_actions_ = identity_actions_ && env_low_[i] == -1.0 && env_high_[i] == 1.0;
  }
  action_spec_ = actions;
  action_spec_.low.assign(actions.size(), -1.0);
  action_spec_.high.assign(actions.size(), 1.0);
  const py::object spec = py::getattr(env_, "spec", py::none());
  const py::object steps =
      spec.is_none() ? py::none() : py::getattr(spec, "max_episode_steps", py::none());
  if (py::isinstance<py::int_>(steps)) max_episode_steps_ = steps.cast<int>();
  const py::object dt = py::getattr(py::getattr(env_, "unwrapped", env_), "dt", py::none());
  if (!dt.is_none()) step_seconds_ = Number(dt, "dt");
}

PythonEnv::~PythonEnv() {
  py::gil_scoped_acquire acquire;
  env_ = py::object();
}

std::string PythonEnv::Where() const {
  return fmt::format("the environment {}, episode {}, step {}", name_, episode_, episode_step_);
}

double PythonEnv::Number(const py::handle& value, const char* what) const {
  try {
    return py::cast<double>(value);
  } catch (const py::cast_error&) {
    Fail("{}: the {} is {}: expected a real number", Where(), what, std::string(py::repr(value)));
  }
}

bool PythonEnv::Flag(const py::handle& value, const char* what) const {
  try {
    return py::cast<bool>(value);
  } catch (const py::cast_error&) {
    Fail("{}: {} is {}: expected a boolean", Where(), what, std::string(py::repr(value)));
  }
}

void PythonEnv::ReadKnownInfo(const py::dict& info, StepInfo& out) const {
  if (info.contains("goal_met")) out.goal_met = Flag(info["goal_met"], "info['goal_met']");
  const std::pair<const char*, double StepInfo::*> costs[] = {
      {"cost_hazards", &StepInfo::cost_hazards},
      {"cost_vases_contact", &StepInfo::cost_vases_contact},
      {"cost_vases_velocity", &StepInfo::cost_vases_velocity},
      {"cost_buttons", &StepInfo::cost_buttons},
      {"cost_gremlins", &StepInfo::cost_gremlins},
      {"cost_pillars", &StepInfo::cost_pillars},
      {"cost_out_of_boundary", &StepInfo::cost_out_of_boundary}};
  for (const auto& [key, member] : costs) {
    if (info.contains(key)) out.*member = Number(info[key], "info cost");
  }
}

std::vector<double> PythonEnv::Observation(const py::handle& value, const char* call) const {
  std::vector<double> observation;
  try {
    observation =
        RealValues(value, {static_cast<py::ssize_t>(observation_spec_.size())}, "the observation");
  } catch (const Error& error) {  // named with the step only now: this runs every step
    Fail("{}: {}: {}", Where(), call, error.what());
  }
  for (size_t i = 0; i < observation.size(); ++i) {
    if (!std::isfinite(observation[i])) {
      Fail("{}: {}: the observation holds {} at component {}: expected finite values", Where(),
           call, observation[i], i);
    }
  }
  return observation;
}

std::vector<double> PythonEnv::Reset(std::optional<std::uint64_t> seed) {
  py::gil_scoped_acquire acquire;
  ++episode_;
  episode_step_ = 0;
  py::object result;
  try {
    result = seed ? env_.attr("reset")(py::arg("seed") = *seed) : env_.attr("reset")();
  } catch (py::error_already_set& error) {
    Fail("{}: reset() raised {}", Where(), PythonErrorText(error));
  }
  if (!py::isinstance<py::tuple>(result) || py::len(result) != 2) {
    Fail("{}: reset() returned {}: expected (observation, info)", Where(),
         std::string(py::repr(result)).substr(0, 200));
  }
  return Observation(result[py::int_(0)], "reset()");
}

std::vector<double> PythonEnv::EnvAction(const std::vector<double>& action) const {
  if (identity_actions_) return action;
  std::vector<double> mapped(action.size());
  for (size_t i = 0; i < action.size(); ++i) {
    mapped[i] = env_low_[i] + (action[i] + 1.0) * 0.5 * (env_high_[i] - env_low_[i]);
  }
  return mapped;
}

StepResult PythonEnv::Step(const std::vector<double>& action) {
  if (static_cast<int>(action.size()) != action_spec_.size()) {
    Fail("the action has {} entries: expected {}", action.size(), action_spec_.size());
  }
  std::vector<double> mapped = EnvAction(action);
  py::gil_scoped_acquire acquire;
  ++episode_step_;
  py::object result;
  try {
    result = env_.attr("step")(Own(std::move(mapped)));
  } catch (py::error_already_set& error) {
    Fail("{}: step() raised {}", Where(), PythonErrorText(error));
  }
  // Messages are built only on failure: this runs every step.
  const py::ssize_t values = py::isinstance<py::tuple>(result) ? py::len(result) : 0;
  if (values != 5 && values != 6) {
    Fail(
        "{}: step() returned {}: expected Safety-Gymnasium's (observation, reward, cost, "
        "terminated, truncated, info) or Gymnasium's (observation, reward, terminated, "
        "truncated, info) with info['cost']",
        Where(), std::string(py::repr(result)).substr(0, 200));
  }
  const py::tuple t = result;
  StepResult step;
  step.observation = Observation(t[0], "step()");
  step.reward = Number(t[1], "reward");
  const int flags = values == 6 ? 3 : 2;
  step.terminated = Flag(t[flags], "terminated");
  step.truncated = Flag(t[flags + 1], "truncated");
  const py::handle info = t[values - 1];
  const bool info_is_dict = py::isinstance<py::dict>(info);
  if (info_is_dict) ReadKnownInfo(info.cast<py::dict>(), step.info);
  if (values == 6) {
    step.info.raw_cost = Number(t[2], "cost");
  } else {
    if (!info_is_dict || !info.cast<py::dict>().contains("cost")) {
      Fail(
          "{}: step() returned five values and its info has no 'cost': expected "
          "info['cost'] (Safety-Gymnasium's five-value form), or a sixth value",
          Where());
    }
    step.info.raw_cost = Number(info.cast<py::dict>()["cost"], "cost");
  }
  if (!std::isfinite(step.reward) || !std::isfinite(step.info.raw_cost)) {
    Fail("{}: step() returned reward {} and cost {}: expected finite numbers", Where(), step.reward,
         step.info.raw_cost);
  }
  step.cost = step.info.raw_cost > 0.0 ? 1.0 : 0.0;
  step.info.env_steps = 1;
  return step;
}

std::optional<std::string> PythonEnv::Pickled(std::string* why) const {
  try {
    return std::string(py::bytes(py::module_::import("pickle").attr("dumps")(env_)));
  } catch (py::error_already_set& error) {
    if (why != nullptr) *why = error.what();
    return std::nullopt;
  }
}

void PythonEnv::Unpickle(const std::string& bytes) {
  py::object env;
  try {
    env = py::module_::import("pickle").attr("loads")(py::bytes(bytes));
  } catch (py::error_already_set& error) {
    Fail("the environment {}'s saved state does not unpickle: {}", name_, PythonErrorText(error));
  }
  const BoxSpec observations = BoxOf(env.attr("observation_space"), "observation_space", name_);
  const BoxSpec actions = BoxOf(env.attr("action_space"), "action_space", name_);
  Require(observations.size() == observation_spec_.size() && actions.low == env_low_ &&
              actions.high == env_high_,
          "the environment {}'s saved state is of another environment (its spaces differ)", name_);
  env_ = std::move(env);
}

std::string PythonEnv::GeneratorState() const {
  py::gil_scoped_acquire acquire;
  const std::optional<std::string> bytes = Pickled(nullptr);
  if (!bytes) return "";
  const py::object text =
      py::module_::import("base64").attr("b64encode")(py::bytes(*bytes)).attr("decode")("ascii");
  return kPickledPrefix + text.cast<std::string>();
}

void PythonEnv::SetGeneratorState(const std::string& state) {
  if (state.empty()) return;  // it did not pickle: the environment goes on as it is
  const std::string prefix = kPickledPrefix;
  Require(state.rfind(prefix, 0) == 0,
          "the environment {}'s saved state is not one it wrote (expected '{}...')", name_, prefix);
  py::gil_scoped_acquire acquire;
  std::string bytes;
  try {
    bytes = py::bytes(py::module_::import("base64").attr("b64decode")(state.substr(prefix.size())));
  } catch (py::error_already_set& error) {
    Fail("the environment {}'s saved state is damaged: {}", name_, PythonErrorText(error));
  }
  Unpickle(bytes);
}

std::string PythonEnv::State() const {
  py::gil_scoped_acquire acquire;
  std::string why;
  const std::optional<std::string> bytes = Pickled(&why);
  Require(bytes.has_value(), "the environment {} does not pickle, so its state cannot be saved: {}",
          name_, why);
  return *bytes;
}

std::optional<std::string> PythonEnv::TryState() const {
  py::gil_scoped_acquire acquire;
  return Pickled(nullptr);
}

std::optional<RgbFrame> PythonEnv::Frame() {
  py::gil_scoped_acquire acquire;
  const py::object mode = py::getattr(env_, "render_mode", py::none());
  if (mode.is_none() || std::string(py::str(mode)) != "rgb_array") return std::nullopt;
  py::object result;
  try {
    result = env_.attr("render")();
  } catch (py::error_already_set& error) {
    Fail("{}: render() raised {}", Where(), PythonErrorText(error));
  }
  const auto pixels = py::array_t<std::uint8_t, py::array::c_style>::ensure(result);
  const py::array given = py::array::ensure(result);
  Require(pixels && given && given.dtype().kind() == 'u' && given.itemsize() == 1 &&
              pixels.ndim() == 3 && (pixels.shape(2) == 3 || pixels.shape(2) == 4) &&
              pixels.shape(0) >= 1 && pixels.shape(1) >= 1,
          "{}: render() in rgb_array mode returned {}: expected an (H, W, 3) uint8 array",
          Where(), std::string(py::repr(py::getattr(result, "shape", result))));
  RgbFrame frame;
  frame.height = static_cast<int>(pixels.shape(0));
  frame.width = static_cast<int>(pixels.shape(1));
  const py::ssize_t channels = pixels.shape(2);
  frame.rgb.reserve(static_cast<size_t>(frame.width) * frame.height * 3);
  const std::uint8_t* data = pixels.data();
  for (py::ssize_t i = 0; i < static_cast<py::ssize_t>(frame.width) * frame.height; ++i) {
    frame.rgb.insert(frame.rgb.end(), data + i * channels, data + i * channels + 3);
  }
  return frame;
}

void PythonEnv::SetState(const std::string& state) {
  py::gil_scoped_acquire acquire;
  Unpickle(state);
}

}  // namespace cmbrl::python

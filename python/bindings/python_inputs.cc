#include "python/bindings/python_inputs.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <torch/torch.h>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/planning/reward_term.h"
#include "python/bindings/arrays.h"

namespace cmbrl::python {
namespace {

// A float32 tensor's rows as a new (rows, width) float64 numpy array: what a Python reward reads.
// The array owns the converted tensor (no second copy).
py::array_t<double> RowsArray(const torch::Tensor& values, std::int64_t rows) {
  auto host = std::make_unique<torch::Tensor>(values.to(torch::kCPU, torch::kDouble).contiguous());
  double* data = host->data_ptr<double>();
  const auto width = static_cast<py::ssize_t>(host->numel() / rows);
  py::capsule owner(host.get(), [](void* p) { delete static_cast<torch::Tensor*>(p); });
  host.release();  // the capsule owns it now
  return py::array_t<double>({static_cast<py::ssize_t>(rows), width}, data, owner);
}

// A vectorised Python function of every predicted step of an evaluation at once, f(states,
// actions, next_states) -> (N,): N = H x E' x samples rows, states and next_states (N, S),
// actions (N, A), float64. Holds the GIL only for the call. Not thread-safe.
class PythonStepFunction {
 public:
  PythonStepFunction(py::object function, const char* kind)
      : function_(std::move(function)), kind_(kind) {}
  ~PythonStepFunction() {
    py::gil_scoped_acquire acquire;
    function_ = py::object();
  }

  // The function's N values for the steps (leading shape of next_states); throws cmbrl::Error
  // naming the function for an exception it raises or a result that is not N real numbers.
  std::vector<double> Call(const torch::Tensor& states, const torch::Tensor& actions,
                           const torch::Tensor& next_states) const {
    const std::int64_t rows = next_states.numel() / next_states.size(-1);
    py::gil_scoped_acquire acquire;
    py::object result;
    try {
      result = function_(RowsArray(states, rows), RowsArray(actions, rows),
                         RowsArray(next_states, rows));
    } catch (py::error_already_set& error) {
      Fail("the {} function {} raised {} (it is called as {}(states, actions, next_states), "
           "arrays of {} rows, and returns {} values)",
           kind_, Name(), PythonErrorText(error), kind_, rows, rows);
    }
    // Booleans (a termination's) read as 0 and 1.
    const py::array array = py::array::ensure(result);
    if (array && array.dtype().kind() == 'b') result = array.attr("astype")("float64");
    try {
      return RealValues(result, {static_cast<py::ssize_t>(rows)}, "the result");
    } catch (const Error& error) {  // named only now: this runs at every planner iteration
      Fail("the {} function {}: {}", kind_, Name(), error.what());
    }
  }

  // Values shaped as the steps, on their device.
  static torch::Tensor AsSteps(const std::vector<double>& values, const torch::Tensor& steps) {
    std::vector<std::int64_t> shape(steps.sizes().begin(), steps.sizes().end() - 1);
    // from_blob: the values are copied once, by the conversion to float32.
    return torch::from_blob(const_cast<double*>(values.data()),
                            {static_cast<std::int64_t>(values.size())}, torch::kDouble)
        .to(steps.device(), torch::kFloat)
        .view(shape);
  }

  std::string Name() const {
    py::gil_scoped_acquire acquire;
    return std::string(py::str(py::getattr(function_, "__qualname__", py::repr(function_))));
  }

 private:
  py::object function_;
  const char* kind_;
};

// objective.reward: python. The planning objective's reward term from a reward function (see
// PythonStepFunction), called once per evaluation (a planner iteration); the cost is minus the
// reward. Throws cmbrl::Error naming the function for a reward that is not finite.
class PythonRewardTerm final : public RewardTerm {
 public:
  explicit PythonRewardTerm(py::object reward) : reward_(std::move(reward), "reward") {}

  torch::Tensor Cost(const torch::Tensor& states, const torch::Tensor& actions,
                     const torch::Tensor& next_states) const override {
    const std::vector<double> rewards = reward_.Call(states, actions, next_states);
    for (const double reward : rewards) {  // the name is looked up only for a message
      if (!std::isfinite(reward)) {
        Fail("the reward function {} returned {}: expected finite rewards", reward_.Name(), reward);
      }
    }
    return -PythonStepFunction::AsSteps(rewards, next_states);
  }
  bool reads_states_and_actions() const override { return true; }

 private:
  PythonStepFunction reward_;
};

// objective.termination: python. Where predicted steps end the episode, from a function (see
// PythonStepFunction) that returns N booleans or 0/1 numbers. Throws cmbrl::Error naming the
// function for another value.
class PythonTerminationTerm final : public TerminationTerm {
 public:
  explicit PythonTerminationTerm(py::object termination)
      : termination_(std::move(termination), "termination") {}

  torch::Tensor Terminal(const torch::Tensor& states, const torch::Tensor& actions,
                         const torch::Tensor& next_states) const override {
    const std::vector<double> terminal = termination_.Call(states, actions, next_states);
    for (const double value : terminal) {  // the name is looked up only for a message
      if (value != 0.0 && value != 1.0) {
        Fail("the termination function {} returned {}: expected booleans (or 0 and 1)",
             termination_.Name(), value);
      }
    }
    return PythonStepFunction::AsSteps(terminal, next_states);
  }

 private:
  PythonStepFunction termination_;
};

// "role=module.qualname" of a function given, for the run's sessions.
std::string Named(const char* role, const py::handle& function) {
  const py::object module = py::getattr(function, "__module__", py::none());
  const py::object name = py::getattr(function, "__qualname__", py::repr(function));
  return fmt::format("{}={}{}", role,
                     module.is_none() ? std::string() : std::string(py::str(module)) + ".",
                     std::string(py::str(name)));
}

// The object `declared` ("module:attribute") names under python.`key`, its module imported with
// `path` first on sys.path; throws cmbrl::Error naming the key for what fails.
py::object ImportDeclared(const char* key, const std::string& declared,
                          const std::vector<std::string>& path) {
  py::list sys_path = py::module_::import("sys").attr("path");
  for (auto folder = path.rbegin(); folder != path.rend(); ++folder) {
    if (!sys_path.contains(*folder)) sys_path.insert(0, *folder);
  }
  const size_t colon = declared.find(':');
  const std::string module_name = declared.substr(0, colon);
  py::object object;
  try {
    object = py::module_::import(module_name.c_str());
  } catch (py::error_already_set& error) {
    Fail("python.{} is '{}': importing module '{}' raised {} (python.path: [{}])", key, declared,
         module_name, PythonErrorText(error), fmt::join(path, ", "));
  }
  std::string attribute = declared.substr(colon + 1);
  for (size_t from = 0;;) {
    const size_t dot = attribute.find('.', from);
    const std::string part = attribute.substr(from, dot == std::string::npos ? dot : dot - from);
    Require(py::hasattr(object, part.c_str()), "python.{} is '{}': '{}' has no attribute '{}'", key,
            declared, std::string(py::str(py::getattr(object, "__name__", py::repr(object)))),
            part);
    object = object.attr(part.c_str());
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
  Require(PyCallable_Check(object.ptr()) != 0, "python.{} is '{}': {} is not callable", key,
          declared, std::string(py::repr(object)));
  return object;
}

}  // namespace

std::shared_ptr<py::object> GilHeld(py::object object) {
  return std::shared_ptr<py::object>(new py::object(std::move(object)), [](py::object* held) {
    py::gil_scoped_acquire acquire;
    delete held;
  });
}

GivenEnv::GivenEnv(py::object f, std::string n)
    : factory(GilHeld(std::move(f))),
      name(std::move(n)),
      first(std::make_shared<std::unique_ptr<PythonEnv>>(Make(*factory, name))) {}

std::unique_ptr<PythonEnv> GivenEnv::Make(const py::object& factory, const std::string& name,
                                          bool drawing) {
  py::object env;
  try {
    env = drawing ? factory(py::arg("render_mode") = "rgb_array") : factory();
  } catch (py::error_already_set& error) {
    Fail("making the environment {}{} raised {}", name,
         drawing ? " with render_mode='rgb_array'" : "", PythonErrorText(error));
  }
  return std::make_unique<PythonEnv>(std::move(env), name);
}

bool GivenEnv::takes_render_mode() const {
  try {
    const py::object parameters =
        py::module_::import("inspect").attr("signature")(*factory).attr("parameters");
    if (parameters.contains("render_mode")) return true;
    for (const py::handle parameter : parameters.attr("values")()) {
      if (std::string(py::str(parameter.attr("kind").attr("name"))) == "VAR_KEYWORD") return true;
    }
  } catch (py::error_already_set&) {  // a builtin without a signature: assume not
  }
  return false;
}

std::string GivenEnv::task() const { return kPythonTaskPrefix + name; }

LearnerInputs InputsWith(const std::optional<py::function>& reward,
                         const std::optional<py::function>& termination,
                         const std::optional<GivenEnv>& env) {
  LearnerInputs inputs;
  std::vector<std::string> names;
  if (env) names.push_back("env=" + env->name);
  if (reward) names.push_back(Named("reward", *reward));
  if (termination) names.push_back(Named("termination", *termination));
  inputs.python_functions = fmt::format("{}", fmt::join(names, ", "));
  if (reward) {
    inputs.python_reward = [function = GilHeld(*reward)]() -> std::unique_ptr<RewardTerm> {
      py::gil_scoped_acquire acquire;
      return std::make_unique<PythonRewardTerm>(*function);
    };
  }
  if (termination) {
    inputs.python_termination = [function =
                                     GilHeld(*termination)]() -> std::unique_ptr<TerminationTerm> {
      py::gil_scoped_acquire acquire;
      return std::make_unique<PythonTerminationTerm>(*function);
    };
  }
  if (env) {
    inputs.python_env = [given = *env]() -> std::unique_ptr<Env> {
      py::gil_scoped_acquire acquire;
      if (*given.first) return std::move(*given.first);
      return GivenEnv::Make(*given.factory, given.name);
    };
    if (env->takes_render_mode()) {
      inputs.python_render_env = [given = *env]() -> std::unique_ptr<Env> {
        py::gil_scoped_acquire acquire;
        return GivenEnv::Make(*given.factory, given.name, /*drawing=*/true);
      };
    }
    inputs.python_task = env->task();
    inputs.observation_size = (*env->first)->observation_spec().size();
    inputs.action_size = (*env->first)->action_spec().size();
  }
  return inputs;
}

LearnerInputs DeclaredInputs(const PythonSourceOptions& declared) {
  std::optional<GivenEnv> env;
  std::optional<py::function> reward, termination;
  if (!declared.env.empty()) {
    env.emplace(ImportDeclared("env", declared.env, declared.path), DeclaredEnvName(declared.env));
  }
  if (!declared.reward.empty()) {
    reward = py::reinterpret_borrow<py::function>(
        ImportDeclared("reward", declared.reward, declared.path));
  }
  if (!declared.termination.empty()) {
    termination = py::reinterpret_borrow<py::function>(
        ImportDeclared("termination", declared.termination, declared.path));
  }
  return InputsWith(reward, termination, env);
}

void InstallDeclaredInputsMaker() {
  SetPythonInputsMaker([](const PythonSourceOptions& declared) {
    py::gil_scoped_acquire acquire;
    return DeclaredInputs(declared);
  });
}

}  // namespace cmbrl::python

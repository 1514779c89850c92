// What a run is given from Python, as cmbrl's LearnerInputs: an environment (a zero-argument
// factory), and the planning objective's reward and termination functions; given by the caller
// (cmbrl.train(env=..., reward=..., termination=...)) or declared by name in the config's
// python section and imported here. Used by the Python module and by the command line, which
// runs an interpreter of its own for a config that declares them.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>

#include "cmbrl/config/python_source.h"
#include "cmbrl/learners/learner_inputs.h"
#include "python/bindings/python_env.h"

namespace cmbrl::python {

namespace py = pybind11;

// A Python object that may outlive the GIL's holder: dropped with the GIL taken, so that the
// LearnerInputs holding it can be destroyed from any thread.
std::shared_ptr<py::object> GilHeld(py::object object);

// An environment given from Python: a zero-argument factory and what made it (the run's task is
// "python:" + name). Its first environment is made at once (its sizes name the run's) and is the
// first the learner gets; later ones come from the factory. Make it with the GIL held.
struct GivenEnv {
  std::shared_ptr<py::object> factory;
  std::string name;
  std::shared_ptr<std::unique_ptr<PythonEnv>> first;

  GivenEnv(py::object f, std::string n);

  // A new environment from the factory (with render_mode="rgb_array" where `drawing`); throws
  // cmbrl::Error naming what it raised.
  static std::unique_ptr<PythonEnv> Make(const py::object& factory, const std::string& name,
                                         bool drawing = false);
  // Whether the factory takes render_mode (a parameter of that name, or **kwargs).
  bool takes_render_mode() const;
  std::string task() const;
};

// LearnerInputs with the Python environment, reward and termination functions that are given
// (the environment's task and sizes filled in). Call with the GIL held.
LearnerInputs InputsWith(const std::optional<py::function>& reward,
                         const std::optional<py::function>& termination,
                         const std::optional<GivenEnv>& env = std::nullopt);

// The LearnerInputs a config's python section declares: each "module:attribute" imported with
// the folders of declared.path first on sys.path (once each). Throws cmbrl::Error naming the key
// and what failed (a module that does not import, a missing attribute, one not callable). Call
// with the GIL held.
LearnerInputs DeclaredInputs(const PythonSourceOptions& declared);

// Lets cmbrl's core make declared Python parts in this process (SetPythonInputsMaker), with the
// interpreter already running (the Python module's).
void InstallDeclaredInputsMaker();

}  // namespace cmbrl::python

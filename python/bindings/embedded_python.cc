#include "python/bindings/embedded_python.h"

#include <pybind11/embed.h>

#include <mutex>

#include "cmbrl/learners/learner_inputs.h"
#include "python/bindings/python_inputs.h"

namespace cmbrl::python {

void InstallEmbeddedPython() {
  SetPythonInputsMaker([](const PythonSourceOptions& declared) {
    static std::once_flag started;
    std::call_once(started, [] {
      py::initialize_interpreter(/*init_signal_handlers=*/false);
      // Last on the path: an installed cmbrl, or one a user's PYTHONPATH names, comes first.
      py::module_::import("sys").attr("path").attr("append")(CMBRL_PYTHON_PACKAGE_DIR);
      // Never finalised: Python objects the run holds may be dropped as late as the process's
      // exit. The GIL is taken for each call from here on, from any thread.
      PyEval_SaveThread();
    });
    py::gil_scoped_acquire acquire;
    return DeclaredInputs(declared);
  });
}

}  // namespace cmbrl::python

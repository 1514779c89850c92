// cmbrl's Python module, the compiled half (`cmbrl._cmbrl`): environments, vectors of them,
// the learned models, training and trained runs, results. python/cmbrl/__init__.py builds the
// Gymnasium-style surface on it. Every long call (stepping, planning, training) releases the
// GIL; cmbrl::Error becomes cmbrl.Error (a ValueError) with the same message.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "cmbrl/core/build_info.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"
#include "python/bindings/bindings.h"
#include "python/bindings/python_inputs.h"

PYBIND11_MODULE(_cmbrl, m) {
  namespace py = pybind11;
  m.doc() = "cmbrl's compiled core; use the cmbrl package";
  m.attr("__version__") = cmbrl::CmbrlVersion();
  m.attr("__commit__") = cmbrl::CmbrlCommit();
  py::register_exception<cmbrl::Error>(m, "Error", PyExc_ValueError)
      .doc() = "An error of cmbrl's core: its message names the bad value and what was expected.";
  m.def(
      "did_you_mean",
      [](const std::string& name, const std::vector<std::string>& candidates) {
        return cmbrl::DidYouMean(name, candidates);
      },
      py::arg("name"), py::arg("candidates"),
      "\" (did you mean 'x'?)\" for the one candidate near enough to be a slip, else \"\" (the "
      "rule of the core's messages)");
  cmbrl::python::BindEnvs(m);
  cmbrl::python::BindModels(m);
  cmbrl::python::BindRuns(m);
  cmbrl::python::BindResults(m);
  // Runs whose config declares Python parts by name make them in this interpreter.
  cmbrl::python::InstallDeclaredInputsMaker();
}

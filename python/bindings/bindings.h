// The parts of the Python module (`cmbrl._cmbrl`, module.cc), one per concept, and what they
// share.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <mutex>
#include <vector>

namespace cmbrl {
class DynamicsModel;
class EnsembleDynamics;
class XgbCostModel;
}  // namespace cmbrl

namespace cmbrl::python {

namespace py = pybind11;

// Serialises the calls of one Python-facing object (an Env, a VectorEnv, an Agent, a model):
// two Python threads that share it take turns, while distinct objects still run in parallel.
// The lock is taken with the GIL released, so that a thread waiting for it never holds the GIL
// its holder needs to finish; hold one for a whole call, from its first line.
class ObjectLock {
 public:
  explicit ObjectLock(std::mutex& mutex) : lock_(mutex, std::defer_lock) {
    if (lock_.try_lock()) return;  // uncontended: no need to give up the GIL
    py::gil_scoped_release release;
    lock_.lock();
  }

 private:
  std::unique_lock<std::mutex> lock_;
};

// One field of a C++ struct as a Python dict gives it: its key beside the member it reads.
template <typename Struct, typename Value>
struct DictField {
  const char* key;
  Value Struct::*member;
};

// The field `key` of a dict, read from `member` (Field("epochs", &FitReport::epochs)).
template <typename Struct, typename Value>
DictField<Struct, Value> Field(const char* key, Value Struct::*member) {
  return {key, member};
}

// A struct's fields as a dict, each named once beside its member (AsDict(report,
// Field("epochs", &FitReport::epochs), ...)): the one conversion of the module's reports and
// summaries.
template <typename Struct, typename... Values>
py::dict AsDict(const Struct& value, const DictField<Struct, Values>&... fields) {
  py::dict d;
  ((d[fields.key] = value.*(fields.member)), ...);
  return d;
}

void BindEnvs(py::module_& m);    // envs.cc: Env, VectorEnv, env_names, bench_env
void BindModels(py::module_& m);  // models.cc: Ensemble, CostClassifier
void BindRuns(py::module_& m);    // runs.cc: Agent, train
void BindResults(py::module_& m);  // results.cc: read_runs, report

// Every member's next state for n rows of states (N, S) and actions (N, A): (E, N, S).
py::array_t<double> PredictNextStates(const DynamicsModel& dynamics,
                                      const std::vector<double>& states,
                                      const std::vector<double>& actions, py::ssize_t n);

// The classifier's verdict on states (N, S): (N) bool.
py::array PredictViolations(const XgbCostModel& classifier, const py::handle& states);

}  // namespace cmbrl::python

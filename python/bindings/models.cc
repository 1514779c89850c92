// The learned models in Python, without a run: the dynamics ensemble (Ensemble) and the
// constraint classifier (CostClassifier) on numpy arrays; also the predictions a trained run's
// agent gives from its own models.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <torch/torch.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/memory.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/step_model.h"
#include "cmbrl/models/transition_buffer.h"
#include "cmbrl/models/xgboost_cost_model.h"
#include "python/bindings/arrays.h"
#include "python/bindings/bindings.h"

namespace cmbrl::python {
namespace {

// A fit's keep-going callback, called between epochs or boosting rounds with the GIL released:
// runs Python's signal handlers, false once one raised (Ctrl-C's KeyboardInterrupt).
bool NoSignalRaised() {
  const py::gil_scoped_acquire acquire;
  return PyErr_CheckSignals() == 0;
}

}  // namespace

py::array_t<double> PredictNextStates(const DynamicsModel& dynamics,
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
    out = ToDoubles(
        dynamics.Predict(rows(states, dynamics.state_dim()), rows(actions, dynamics.action_dim())));
  }
  return Own<double>(std::move(out), {members, n, dynamics.state_dim()});
}

py::array PredictViolations(const XgbCostModel& classifier, const py::handle& states) {
  const py::ssize_t n = RowsOf(states, "states");
  const std::vector<double> sv = Matrix(states, n, classifier.state_dim(), "states");
  const std::vector<float> rows(sv.begin(), sv.end());
  std::vector<std::uint8_t> out;
  {
    py::gil_scoped_release release;
    out = classifier.PredictRows(rows.data(), static_cast<int>(n));
  }
  return Flags(out);
}

namespace {

// A dynamics ensemble of its own, fitted on the caller's transitions (a ring of 500k, as in
// training: each fit adds the new ones and trains on all, warm-started after the first). Not
// thread-safe.
// Thread-safe: calls from several Python threads take turns (ObjectLock).
class PyEnsemble {
 public:
  PyEnsemble(int state_dim, int action_dim, int ensemble_size, const std::vector<int>& hidden,
             int max_epochs, bool predict_delta, std::uint64_t seed)
      : buffer_(state_dim, action_dim),
        dynamics_(state_dim, action_dim,
                  Options(ensemble_size, hidden, max_epochs, predict_delta), seed) {}

  py::dict Fit(const py::handle& states, const py::handle& actions, const py::handle& next_states) {
    const ObjectLock lock(mutex_);
    const py::ssize_t n = RowsOf(states, "states");
    const int s = dynamics_.state_dim(), a = dynamics_.action_dim();
    // The arrays' double copies, the buffer's float rows (old and new) and the fit's tensors.
    const double values = 2.0 * s + a;
    RequireMemory(static_cast<double>(n) * values * 8.0 +
                      (static_cast<double>(buffer_.size()) + n) * values * 4.0 * 4.0,
                  fmt::format("fitting the ensemble on {} more transitions (it holds {})", n,
                              buffer_.size()),
                  "fit on fewer transitions");
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
      // After each epoch, Python's signal handlers run (Ctrl-C): a KeyboardInterrupt stops the
      // fit there, the epochs done kept, and is raised once the fit has returned.
      report = dynamics_.Fit(buffer_, NoSignalRaised);
    }
    if (report.interrupted && PyErr_Occurred() != nullptr) throw py::error_already_set();
    using R = EnsembleFitReport;
    py::dict d = AsDict(report, Field("epochs", &R::epochs), Field("train_size", &R::train_size),
                        Field("validation_size", &R::validation_size),
                        Field("train_mse", &R::train_mse),
                        Field("validation_mse", &R::validation_mse),
                        Field("stopped_early", &R::stopped_early), Field("seconds", &R::seconds));
    // Whose products ran: the predictions' and the training's (ensemble.backend's auto rule).
    d["backend"] = dynamics_.backend();
    d["training_backend"] = dynamics_.training_backend();
    return d;
  }

  // states (N, S), actions (N, A) -> every member's next state (E, N, S).
  py::array_t<double> Predict(const py::handle& states, const py::handle& actions) const {
    const ObjectLock lock(mutex_);
    Require(buffer_.size() > 0,
            "Ensemble.predict before fit: its networks are untrained; fit it on transitions "
            "first, or load a fitted one");
    const py::ssize_t n = RowsOf(states, "states");
    return PredictNextStates(dynamics_, Matrix(states, n, dynamics_.state_dim(), "states"),
                             Matrix(actions, n, dynamics_.action_dim(), "actions"), n);
  }

  int transitions() const { return buffer_.size(); }

  // The networks, optimiser and generator (ensemble.pt) and the transitions held
  // (transitions.bin) into `folder`, which must exist: what a later fit continues from.
  void Save(const std::string& folder) const {
    const ObjectLock lock(mutex_);
    py::gil_scoped_release release;
    dynamics_.Save(folder + "/ensemble.pt");
    buffer_.Save(folder + "/transitions.bin");
  }

  void Load(const std::string& folder) {
    const ObjectLock lock(mutex_);
    py::gil_scoped_release release;
    dynamics_.Load(folder + "/ensemble.pt");
    buffer_.Load(folder + "/transitions.bin");
  }

 private:
  mutable std::mutex mutex_;  // ObjectLock: one call at a time
  static EnsembleOptions Options(int ensemble_size, const std::vector<int>& hidden,
                                 int max_epochs, bool predict_delta) {
    EnsembleOptions o;
    o.ensemble_size = ensemble_size;
    o.hidden_sizes = hidden;
    o.max_epochs = max_epochs;
    o.predict_delta = predict_delta;
    return o;
  }

  TransitionBuffer buffer_;
  EnsembleDynamics dynamics_;
};

// A constraint classifier of its own, fitted from scratch on the caller's labelled states. Not
// thread-safe.
// Thread-safe: calls from several Python threads take turns (ObjectLock).
class PyCostClassifier {
 public:
  PyCostClassifier(int state_dim, int rounds, double threshold, std::uint64_t seed)
      : classifier_(state_dim, Options(rounds, threshold), seed) {}

  py::dict Fit(const py::handle& states, const py::handle& unsafe) {
    const ObjectLock lock(mutex_);
    const int s = classifier_.state_dim();
    const py::ssize_t n = RowsOf(states, "states");
    // The array's double copy, the float rows, and XGBoost's matrix and histogram index.
    RequireMemory(static_cast<double>(n) * s * 20.0,
                  fmt::format("fitting the classifier on {} states of {} values", n, s),
                  "fit on fewer states");
    const std::vector<double> sv = Matrix(states, n, s, "states");
    const std::vector<double> labels = RealValues(unsafe, {n}, "unsafe");
    std::vector<float> safe_rows, unsafe_rows;
    for (py::ssize_t i = 0; i < n; ++i) {
      std::vector<float>& to = IsUnsafe(labels, i) ? unsafe_rows : safe_rows;
      to.insert(to.end(), sv.begin() + i * s, sv.begin() + (i + 1) * s);
    }
    CostFitReport report;
    {
      py::gil_scoped_release release;
      // After each boosting round, Python's signal handlers run (Ctrl-C): a KeyboardInterrupt
      // abandons the fit, leaving the classifier as it was, and is raised once it has returned.
      report = classifier_.FitArrays(safe_rows.data(), static_cast<int>(safe_rows.size() / s),
                                     unsafe_rows.data(), static_cast<int>(unsafe_rows.size() / s),
                                     NoSignalRaised);
    }
    if (report.interrupted && PyErr_Occurred() != nullptr) throw py::error_already_set();
    fitted_ = true;
    using R = CostFitReport;
    return AsDict(report, Field("trained", &R::trained), Field("safe_used", &R::safe_used),
                  Field("unsafe_used", &R::unsafe_used), Field("safe_accuracy", &R::safe_accuracy),
                  Field("unsafe_accuracy", &R::unsafe_accuracy), Field("trees", &R::trees),
                  Field("seconds", &R::seconds));
  }

  // The fit set a run's fit would take from these labelled states, stored in their order in a
  // buffer of the run's capacities (XgbCostModel::SelectFitSet): its rows' indices, the safe
  // ones first, as the fit orders them.
  py::array_t<std::int64_t> FitSetRows(const py::handle& states, const py::handle& unsafe) const {
    const ObjectLock lock(mutex_);
    const int s = classifier_.state_dim();
    const py::ssize_t n = RowsOf(states, "states");
    Require(n < (py::ssize_t{1} << 24), "fit_set_rows on {} states: at most 2^24 are numbered", n);
    const std::vector<double> sv = Matrix(states, n, s, "states");
    const std::vector<double> labels = RealValues(unsafe, {n}, "unsafe");
    // Each state carries its row number in one more column (exact in float32 below 2^24), which
    // the selection moves with it.
    LabeledStateBuffer buffer(s + 1);
    std::vector<double> row(static_cast<std::size_t>(s) + 1);
    for (py::ssize_t i = 0; i < n; ++i) {
      std::copy(sv.begin() + i * s, sv.begin() + (i + 1) * s, row.begin());
      row[s] = static_cast<double>(i);
      buffer.Add(row, IsUnsafe(labels, i));
    }
    const XgbCostModel selector(s + 1, classifier_.options(), 0);
    const XgbCostModel::FitSet set = selector.SelectFitSet(buffer);
    std::vector<std::int64_t> rows;
    for (const auto& [values, count] :
         {std::pair(&set.safe, set.safe_count), std::pair(&set.unsafe, set.unsafe_count)}) {
      for (int k = 0; k < count; ++k) {
        rows.push_back(
            static_cast<std::int64_t>((*values)[static_cast<std::size_t>(k) * (s + 1) + s]));
      }
    }
    return py::array_t<std::int64_t>(static_cast<py::ssize_t>(rows.size()), rows.data());
  }

  py::array Predict(const py::handle& states) const {
    const ObjectLock lock(mutex_);
    Require(fitted_,
            "CostClassifier.predict before fit: it has learned nothing (its answer would be "
            "False everywhere); fit it on labelled states first, or load a fitted one");
    return PredictViolations(classifier_, states);
  }

  void Save(const std::string& path) const {
    const ObjectLock lock(mutex_);
    classifier_.Save(path);
  }

  void Load(const std::string& path) {
    const ObjectLock lock(mutex_);
    classifier_.Load(path);
    fitted_ = true;
  }

 private:
  mutable std::mutex mutex_;  // ObjectLock: one call at a time
  bool fitted_ = false;  // fitted or loaded: predict refuses before
  static bool IsUnsafe(const std::vector<double>& labels, py::ssize_t i) {
    Require(labels[i] == 0 || labels[i] == 1, "unsafe[{}] is {}: expected 0 or 1", i, labels[i]);
    return labels[i] != 0;
  }
  static XgbCostModelOptions Options(int rounds, double threshold) {
    XgbCostModelOptions o;
    o.rounds = rounds;
    o.threshold = threshold;
    return o;
  }

  XgbCostModel classifier_;
};

}  // namespace

// A learned reward of its own (StepModel), fitted on the caller's step inputs and rewards.
// Thread-safe: calls from several Python threads take turns (ObjectLock).
class PyRewardModel {
 public:
  PyRewardModel(int input_dim, const std::vector<int>& hidden, int max_epochs, std::uint64_t seed)
      : model_(StepSignal::kReward, input_dim, Options(hidden, max_epochs), seed) {}

  py::dict Fit(const py::handle& inputs, const py::handle& rewards) {
    const ObjectLock lock(mutex_);
    const py::ssize_t n = RowsOf(inputs, "inputs");
    const torch::Tensor x = Rows(Matrix(inputs, n, model_.input_dim(), "inputs"), n);
    const torch::Tensor y = Rows(RealValues(rewards, {n}, "rewards"), n).view({n});
    StepFitReport report;
    {
      py::gil_scoped_release release;
      report = model_.Fit(x, y);
    }
    using R = StepFitReport;  // a reward's losses are mean squared errors
    return AsDict(report, Field("epochs", &R::epochs), Field("train_size", &R::train_size),
                  Field("validation_size", &R::validation_size), Field("train_mse", &R::train_loss),
                  Field("validation_mse", &R::validation_loss), Field("seconds", &R::seconds));
  }

  py::array_t<double> Predict(const py::handle& inputs) {
    const ObjectLock lock(mutex_);
    Require(model_.fitted(),
            "RewardModel.predict before fit: its weights are untrained; fit it first, or load a "
            "fitted one");
    const py::ssize_t n = RowsOf(inputs, "inputs");
    const torch::Tensor x = Rows(Matrix(inputs, n, model_.input_dim(), "inputs"), n);
    std::vector<double> out;
    {
      py::gil_scoped_release release;
      out = ToDoubles(model_.Predict(x));
    }
    return Own(std::move(out));
  }

  void Save(const std::string& path) {
    const ObjectLock lock(mutex_);
    model_.Save(path);
  }
  void Load(const std::string& path) {
    const ObjectLock lock(mutex_);
    model_.Load(path);
  }

 private:
  static StepModelOptions Options(const std::vector<int>& hidden, int max_epochs) {
    StepModelOptions options;
    options.hidden_sizes = hidden;
    options.max_epochs = max_epochs;
    return options;
  }
  // Doubles as (n, width) float32 rows.
  static torch::Tensor Rows(const std::vector<double>& values, py::ssize_t n) {
    return torch::tensor(values, torch::kDouble).to(torch::kFloat).view({n, -1});
  }

  std::mutex mutex_;
  StepModel model_;
};

void BindModels(py::module_& m) {
  py::class_<PyRewardModel>(m, "RewardModel")
      .def(py::init<int, const std::vector<int>&, int, std::uint64_t>(), py::arg("input_dim"),
           py::arg("hidden_sizes"), py::arg("max_epochs"), py::arg("seed"))
      .def("fit", &PyRewardModel::Fit, py::arg("inputs"), py::arg("rewards"))
      .def("predict", &PyRewardModel::Predict, py::arg("inputs"))
      .def("save", &PyRewardModel::Save, py::arg("path"))
      .def("load", &PyRewardModel::Load, py::arg("path"));
  py::class_<PyEnsemble>(m, "Ensemble")
      .def(py::init<int, int, int, const std::vector<int>&, int, bool, std::uint64_t>(),
           py::arg("state_dim"), py::arg("action_dim"), py::arg("ensemble_size"),
           py::arg("hidden_sizes"), py::arg("max_epochs"), py::arg("predict_delta"),
           py::arg("seed"))
      .def("fit", &PyEnsemble::Fit, py::arg("states"), py::arg("actions"), py::arg("next_states"))
      .def("predict", &PyEnsemble::Predict, py::arg("states"), py::arg("actions"))
      .def_property_readonly("transitions", &PyEnsemble::transitions)
      .def("save", &PyEnsemble::Save, py::arg("folder"))
      .def("load", &PyEnsemble::Load, py::arg("folder"));

  py::class_<PyCostClassifier>(m, "CostClassifier")
      .def(py::init<int, int, double, std::uint64_t>(), py::arg("state_dim"), py::arg("rounds"),
           py::arg("threshold"), py::arg("seed"))
      .def("fit", &PyCostClassifier::Fit, py::arg("states"), py::arg("unsafe"))
      .def("fit_set_rows", &PyCostClassifier::FitSetRows, py::arg("states"), py::arg("unsafe"))
      .def("predict", &PyCostClassifier::Predict, py::arg("states"))
      .def("save", &PyCostClassifier::Save, py::arg("path"))
      .def("load", &PyCostClassifier::Load, py::arg("path"));
}

}  // namespace cmbrl::python

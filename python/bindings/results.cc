// Results in Python: the runs of sweeps and experiments as a report reads them (read_runs), and
// the report itself (report), so that a notebook works from the same numbers as `cmbrl report`.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/report/document.h"
#include "cmbrl/report/run_logs.h"
#include "python/bindings/arrays.h"
#include "python/bindings/bindings.h"

namespace cmbrl::python {
namespace {

// One run as a dict: who it is (name, task, method, seed, setting) and its points as numpy
// arrays, one entry per MPC episode or model-free epoch.
py::dict RunAsDict(const RunRecord& run) {
  py::dict d;
  d["name"] = run.name;
  d["task"] = run.config.task;
  d["method"] = MethodOf(run.config);
  d["seed"] = run.config.seed;
  d["setting"] = SettingOf(run);
  d["epoch_log"] = run.epoch_log;
  d["source"] = run.source.string();
  std::vector<std::int64_t> end_step;
  std::vector<std::int64_t> steps;
  std::vector<double> episode_return, episode_cost, cumulative, feasible, elapsed, cpu;
  for (const EpisodePoint& point : run.episodes) {
    end_step.push_back(point.end_step);
    steps.push_back(point.steps);
    episode_return.push_back(point.episode_return);
    episode_cost.push_back(point.episode_cost);
    cumulative.push_back(point.cumulative_violations);
    feasible.push_back(point.feasible_fraction);
    elapsed.push_back(point.elapsed_seconds);
    cpu.push_back(point.cpu_seconds);
  }
  const auto n = static_cast<py::ssize_t>(run.episodes.size());
  d["end_step"] = Own<std::int64_t>(std::move(end_step), {n});
  d["steps"] = Own<std::int64_t>(std::move(steps), {n});
  d["episode_return"] = Own(std::move(episode_return));
  d["episode_cost"] = Own(std::move(episode_cost));
  d["cumulative_violations"] = Own(std::move(cumulative));
  d["feasible_fraction"] = Own(std::move(feasible));
  d["elapsed_seconds"] = Own(std::move(elapsed));
  d["cpu_seconds"] = Own(std::move(cpu));
  return d;
}

}  // namespace

void BindResults(py::module_& m) {
  m.def(
      "read_runs",
      [](const std::vector<std::string>& dirs) {
        std::vector<RunRecord> runs;
        {
          py::gil_scoped_release release;
          runs = ReadSweeps(dirs);
        }
        py::list out;
        for (const RunRecord& run : runs) out.append(RunAsDict(run));
        return out;
      },
      py::arg("dirs"));
  m.def(
      "report",
      [](const std::vector<std::string>& dirs, const std::string& out,
         std::optional<std::int64_t> window, std::optional<std::string> reference, bool complete) {
        ReportRequest request;
        request.sweep_dirs = dirs;
        request.out = out;
        request.window = window;
        request.reference = reference;
        request.complete = complete;
        ReportSummary summary;
        {
          py::gil_scoped_release release;
          summary = WriteReport(request);
        }
        using S = ReportSummary;
        return AsDict(summary, Field("report", &S::report), Field("runs", &S::runs),
                      Field("window", &S::window), Field("cells", &S::cells),
                      Field("left_out", &S::left_out));
      },
      py::arg("dirs"), py::arg("out"), py::arg("window"), py::arg("reference"),
      py::arg("complete"));
}

}  // namespace cmbrl::python

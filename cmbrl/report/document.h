// The report of a sweep or an experiment as files: report.md, Table I as Markdown and CSV, the
// learning curves as PNG and SVG, and the runs' logs (run-logs/) from which it can be made again.
// `cmbrl report` and the Python module call it; it prints nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/report/decision.h"
#include "cmbrl/report/run_logs.h"

namespace cmbrl {

// What an experiment's report records of its declaration (sweep/experiment.h fills it).
struct ExperimentStamp {
  std::string name;           // the experiment's folder name
  std::string dir;            // experiments/<name>, as given
  std::string file;           // experiment.yaml
  std::string sha256;         // of the file
  std::string family;         // "paper", "cpu", ...
  std::string family_sha256;  // of configs/<family>.yaml ("" for the paper family)
  // Its axes' settings ("precision=fp32") in the order the file lists them: the report's order,
  // so that each setting is compared against the first one declared.
  std::vector<std::string> settings;
  // Its declared decision rule (`decision`), which the report applies to "Settings compared".
  std::optional<DecisionRule> decision;
};

struct ReportRequest {
  std::vector<std::string> sweep_dirs;  // sweeps and report folders (their run-logs/)
  std::string out;
  bool complete = false;               // leave out runs that have not reached the window
  std::optional<std::int64_t> window;  // default: the smallest run budget, at most 10,000
  std::int64_t grid_step = 0;          // agent steps between curve points; 0: longest run / 50
  std::int64_t smoothing = 0;          // steps averaged into a point; 0: a tenth of the longest
  std::optional<std::string> reference;     // the original's logs; default: the source tree's
  std::vector<std::string> earlier_tables;  // table-1.csv files of cells whose runs are gone
  std::optional<ExperimentStamp> experiment;  // an experiment's report: its first tables
  // Called with the runs read before anything is written (an experiment checks them against
  // its declaration); throws to refuse them.
  std::function<void(const std::vector<RunRecord>&)> check_runs;
};

struct ReportSummary {
  std::string report;  // out/report.md
  std::size_t runs = 0;
  std::int64_t window = 0;
  std::size_t cells = 0;
  std::size_t earlier_cells = 0;
  std::vector<std::string> left_out;  // runs short of the window: "name (N steps)"
};

// Writes the report into request.out. Throws cmbrl::Error naming a bad input (no runs, a bad
// log, a file that cannot be written).
ReportSummary WriteReport(const ReportRequest& request);

}  // namespace cmbrl

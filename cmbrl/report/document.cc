#include "cmbrl/report/document.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "cmbrl/core/build_info.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/shell.h"
#include "cmbrl/report/curves.h"
#include "cmbrl/report/reference.h"
#include "cmbrl/report/setup_diff.h"
#include "cmbrl/report/table_markdown.h"
#include "cmbrl/run/progress_columns.h"
#include "cmbrl/viz/plot.h"

namespace cmbrl {
namespace {
namespace fs = std::filesystem;

// The order an experiment declares its settings in (ExperimentStamp::settings); none for a sweep.
const std::vector<std::string>& DeclaredSettings(const ReportRequest& args) {
  static const std::vector<std::string> kNone;
  return args.experiment ? args.experiment->settings : kNone;
}

// The local time the report was made, the one line that differs when a report is made again.
std::string Now() {
  const std::time_t now = std::time(nullptr);
  char text[64];
  std::strftime(text, sizeof(text), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return text;
}

std::vector<PlotPanel> CurvePanels(const std::vector<RunRecord>& runs,
                                   const std::vector<RunRecord>& reference,
                                   const std::vector<std::string>& tasks, CurveMetric metric,
                                   const ReportRequest& args, std::int64_t longest,
                                   const std::string& x_label) {
  std::vector<PlotPanel> panels;
  for (const std::string& task : tasks) {
    PlotPanel panel;
    panel.title = task;
    panel.x_label = x_label;
    panel.y_label = metric == CurveMetric::kReturn ? kEpRetColumn : kEpCostColumn;
    if (metric == CurveMetric::kCost) panel.y_floor = 0.0;  // violations are counts
    const std::vector<LearningCurve> curves = LearningCurves(
        runs, task, metric, args.grid_step, args.smoothing, INT64_MAX, DeclaredSettings(args));
    for (const LearningCurve& curve : curves) {
      PlotSeries ours;
      ours.label = WithSetting(MethodLabel(curve.planner), curve.setting);
      ours.x = curve.steps;
      ours.y = curve.mean;
      ours.band = curve.std;
      panel.series.push_back(ours);
    }
    // The original's mean over its seeds, dashed in the colour of its method's first curve of
    // ours (its first setting), over our steps only.
    std::vector<PlotSeries> originals;
    for (const LearningCurve& curve :
         LearningCurves(reference, task, metric, args.grid_step, args.smoothing, longest)) {
      const auto ours = std::find_if(curves.begin(), curves.end(), [&](const LearningCurve& c) {
        return c.planner == curve.planner;
      });
      if (ours == curves.end()) continue;
      PlotSeries original;
      original.label = MethodLabel(curve.planner) + " (original)";
      original.x = curve.steps;
      original.y = curve.mean;
      original.dashed = true;
      original.colour_of = panel.series[static_cast<size_t>(ours - curves.begin())].label;
      originals.push_back(original);
    }
    panel.series.insert(panel.series.end(), originals.begin(), originals.end());
    panels.push_back(panel);
  }
  return panels;
}

// The runs a report counts, and the window it counts them over.
struct CountedRuns {
  std::vector<RunRecord> runs;
  std::int64_t window = kPaperWindow;
  std::vector<std::string> left_out;  // short of the window (--complete)
};

CountedRuns ReadCountedRuns(const ReportRequest& args) {
  CountedRuns counted;
  counted.runs = ReadSweeps(args.sweep_dirs);
  if (args.check_runs) args.check_runs(counted.runs);
  Require(!counted.runs.empty(), "'{}' holds no runs yet", fmt::join(args.sweep_dirs, "', '"));
  for (const RunRecord& run : counted.runs) {
    counted.window = std::min(counted.window, run.config.training.total_steps);
  }
  if (args.window) counted.window = *args.window;
  Require(counted.window >= 1, "--window is {}: expected a positive number of agent steps",
          counted.window);
  if (args.complete) {
    counted.left_out = LeaveOutRunsShortOf(counted.runs, counted.window);
    Require(!counted.runs.empty(), "--complete: no run has reached the window of {} steps",
            counted.window);
  }
  return counted;
}

// The original's runs, and the report's line that says where they came from.
struct ReferenceRuns {
  std::vector<RunRecord> runs;
  std::string note;
};

ReferenceRuns ReadReference(const ReportRequest& args) {
  ReferenceRuns reference;
  const std::string dir = args.reference.value_or(DefaultReferenceDir());
  // A folder someone named (--reference, CMBRL_REFERENCE_DIR) must hold the logs: a wrong one
  // is an error, not a report that quietly lacks the comparison.
  const char* from_environment = std::getenv("CMBRL_REFERENCE_DIR");
  const bool named = args.reference || (from_environment != nullptr && *from_environment != '\0');
  if (named || fs::is_directory(fs::path(dir) / "mbrl")) {
    reference.runs = ReadReferenceRuns(dir);
    // Relative to where the report was made, so that a committed report names no machine's path.
    reference.note = fmt::format("The original's logs: {} runs from '{}'.", reference.runs.size(),
                                 fs::path(dir).lexically_proximate(fs::current_path()).string());
  } else {
    reference.note = fmt::format(
        "The original's logs were not found at '{}' (give --reference DIR): no comparison with "
        "them.",
        dir);
  }
  return reference;
}

// Table I (the runs' cells and those of earlier tables) as table-1.md and table-1.csv.
struct ReportTable {
  std::vector<TableCell> cells;
  std::vector<std::string> earlier_cells;  // "PointGoal1 MPC-RCE": the cells read from earlier
  std::string settings;                    // the settings compared, Markdown ("" for none)
  std::string markdown;                    // table-1.md
};

ReportTable WriteTable(const ReportRequest& args, std::int64_t window,
                       const std::vector<RunRecord>& runs, const std::vector<RunRecord>& reference,
                       const fs::path& out) {
  std::vector<TableCell> earlier;
  for (const std::string& path : args.earlier_tables) {
    const std::vector<TableCell> read = ReadEarlierTable(path, window, reference);
    earlier.insert(earlier.end(), read.begin(), read.end());
  }
  ReportTable table;
  table.cells =
      WithEarlierCells(ViolationTable(runs, window, reference, DeclaredSettings(args)), earlier);
  for (const TableCell& cell : table.cells) {
    if (!cell.source.empty()) {
      table.earlier_cells.push_back(cell.task + " " +
                                    WithSetting(MethodLabel(cell.planner), cell.setting));
    }
  }
  table.settings = SettingComparisonMarkdown(
      table.cells, args.experiment ? args.experiment->decision : std::nullopt);
  // A sweep's report shows the settings compared under Table I; an experiment's, at its top.
  table.markdown =
      TableMarkdown(table.cells, window) + (table.settings.empty() || args.experiment
                                                ? ""
                                                : "\n### Settings compared\n\n" + table.settings);
  WriteFile(out / "table-1.md", table.markdown);
  WriteFile(out / "table-1.csv", TableCsv(table.cells, window));
  return table;
}

// The curves of one learner family's runs (model-free ones against environment steps, 1e7 of
// them, MPC ones against agent steps, each with its own grid), written as PNG and SVG; their
// part of report.md, or "" when the report holds no run of the family.
std::string WriteFamilyCurves(bool model_free, const std::vector<RunRecord>& runs,
                              const std::vector<RunRecord>& reference,
                              const std::vector<std::string>& tasks, const ReportRequest& args,
                              const fs::path& out) {
  std::vector<RunRecord> family, family_reference;
  for (const RunRecord& run : runs) {
    if (run.epoch_log == model_free) family.push_back(run);
  }
  for (const RunRecord& run : reference) {
    if (run.epoch_log == model_free) family_reference.push_back(run);
  }
  if (family.empty()) return "";
  ReportRequest chosen = args;
  std::int64_t longest = 1;
  for (const RunRecord& run : family) longest = std::max(longest, StepsReached(run));
  if (chosen.grid_step == 0) chosen.grid_step = std::max<std::int64_t>(1, longest / 50);
  if (chosen.smoothing == 0) chosen.smoothing = std::max(4 * chosen.grid_step, longest / 10);
  const std::string prefix = model_free ? "curves-model-free-" : "curves-";
  const std::string x_label = model_free ? "environment steps" : "agent steps";
  std::vector<std::string> family_tasks;
  for (const std::string& task : tasks) {
    const bool held = std::any_of(family.begin(), family.end(),
                                  [&](const RunRecord& run) { return run.config.task == task; });
    if (held) family_tasks.push_back(task);
  }
  for (const CurveMetric metric : {CurveMetric::kReturn, CurveMetric::kCost}) {
    const std::string name = prefix + (metric == CurveMetric::kReturn ? "epret" : "epcost");
    WritePlots(
        CurvePanels(family, family_reference, family_tasks, metric, chosen, longest, x_label),
        (out / (name + ".png")).string(), (out / (name + ".svg")).string());
  }
  return fmt::format(
      "{0}A point every {2} {3}: each run's mean over its {4} that ended in the {1} steps "
      "before it, then the mean over seeds; the band is one standard deviation over seeds. "
      "Dashed: the original's mean over its seeds, the same way.\n\n"
      "![EpRet]({5}epret.png)\n\n![EpCost]({5}epcost.png)\n\n",
      model_free ? "### Model-free baselines\n\n" : "", chosen.smoothing, chosen.grid_step, x_label,
      model_free ? "epochs (AverageEpRet, AverageEpCost)" : "episodes", prefix);
}

// An experiment's report opens with its outcome per task and every cell; a sweep's has none.
std::string ExperimentOpening(const ExperimentStamp& e, std::size_t runs,
                              const std::vector<TableCell>& cells, std::int64_t window,
                              const std::string& settings) {
  return fmt::format(
      "# Experiment report: {0}\n\nMade by `cmbrl report {1}` on {2} with cmbrl {3}.\n\n"
      "From `{1}/{4}` (SHA-256 {5}){10} and the logs of its {6}{7} (run-logs/).\n\n"
      "## Outcome per task\n\n{8}\n## Every cell\n\n{9}\n{11}",
      e.name, ShellWord(e.dir), Now(), fmt::format("{} ({})", CmbrlVersion(), CmbrlCommit()),
      e.file, e.sha256,
      RunCount(runs),
      // Runs still going are not named: the committed report must come out the same from
      // its committed logs alone, where they are absent (the summary names them).
      std::string(), ProtocolVerdictMarkdown(cells, window), ProtocolCellsMarkdown(cells, window),
      e.family_sha256.empty()
          ? std::string()
          : fmt::format(", the family `configs/{}.yaml` (SHA-256 {})", e.family, e.family_sha256),
      settings.empty() ? std::string() : "## Settings compared\n\n" + settings + "\n");
}

// The report's sections after Table I and the curves: where the setup and the outcome differ
// from the paper, the compute, and where the runs were made.
std::string DifferenceSections(const CountedRuns& counted, const std::vector<TableCell>& cells,
                               const std::string& reference_note) {
  std::string text;
  for (const std::string& note :
       SetupDifferences(counted.runs, counted.window, DefaultConfigsDir())) {
    text += "- " + note + "\n";
  }
  text += "- " + reference_note + "\n";
  text += "\n## Where the outcome differs\n\n";
  for (const std::string& note : OutcomeDifferences(cells, counted.window)) {
    text += "- " + note + "\n";
  }
  if (const std::string compute = ComputeMarkdown(cells); !compute.empty()) {
    text += "\n## Compute\n\n" + compute;
  }
  text += "\n## Where the runs were made\n\n";
  for (const std::string& note : WhereRunsWereMade(counted.runs)) text += "- " + note + "\n";
  return text;
}

}  // namespace

ReportSummary WriteReport(const ReportRequest& args) {
  const CountedRuns counted = ReadCountedRuns(args);
  const std::vector<RunRecord>& runs = counted.runs;
  const std::int64_t window = counted.window;
  fs::create_directories(args.out);
  const fs::path out(args.out);
  const ReferenceRuns reference = ReadReference(args);

  const ReportTable t = WriteTable(args, window, runs, reference.runs, out);
  const std::vector<TableCell>& cells = t.cells;
  const std::vector<std::string>& earlier_cells = t.earlier_cells;
  std::vector<std::string> tasks;
  for (const TableCell& cell : cells) {
    if (std::find(tasks.begin(), tasks.end(), cell.task) == tasks.end()) tasks.push_back(cell.task);
  }
  std::string curves;
  for (const bool model_free : {false, true}) {
    curves += WriteFamilyCurves(model_free, runs, reference.runs, tasks, args, out);
  }

  std::string report =
      args.experiment ? ExperimentOpening(*args.experiment, runs.size(), cells, window, t.settings)
                      : std::string();
  report += fmt::format(
      "{7} {0}\n\n{1}{4}{5}. Generated by `cmbrl report`; the runs' "
      "`config.yaml`, `progress.csv` and `sessions.jsonl` are kept in run-logs/, from which `cmbrl "
      "report` makes "
      "this report again{6}.\n\n## Table I\n\n{2}\n"
      "## Learning curves\n\n{3}## Where the setup differs from the paper\n\n",
      args.experiment ? args.experiment->name
                      : fs::path(args.sweep_dirs.front()).filename().string(),
      RunCount(runs.size()), t.markdown, curves,
      counted.left_out.empty() || args.experiment
          ? std::string()
          : fmt::format(" (left out, short of the window: {})", fmt::join(counted.left_out, ", ")),
      earlier_cells.empty() ? std::string()
                            : fmt::format(", and {} cells read from earlier tables ({})",
                                          earlier_cells.size(), fmt::join(earlier_cells, ", ")),
      args.earlier_tables.empty()
          ? std::string()
          : fmt::format(" (with --earlier-table '{}')",
                        fmt::join(args.earlier_tables, "' --earlier-table '")),
      args.experiment ? "## Details of" : "# Sweep report:");
  report += DifferenceSections(counted, cells, reference.note);
  WriteFile(out / "report.md", report);
  KeepRunLogs(runs, args.out);
  ReportSummary summary;
  summary.report = (out / "report.md").string();
  summary.runs = runs.size();
  summary.window = window;
  summary.cells = cells.size();
  summary.earlier_cells = earlier_cells.size();
  summary.left_out = counted.left_out;
  return summary;
}

}  // namespace cmbrl

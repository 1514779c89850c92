// `cmbrl report`: Table I and the learning curves of a sweep, as Markdown, CSV, PNG and SVG.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/arguments.h"
#include "app/commands.h"
#include "cmbrl/core/check.h"
#include "cmbrl/report/document.h"
#include "cmbrl/sweep/experiment.h"

namespace cmbrl::app {
namespace {
namespace fs = std::filesystem;



void RunReport(ReportRequest request) {
  const ReportSummary summary = WriteReport(request);
  std::cout << nlohmann::ordered_json{{"report", summary.report},
                                      {"runs", summary.runs},
                                      {"window", summary.window},
                                      {"cells", summary.cells},
                                      {"earlier_cells", summary.earlier_cells},
                                      {"left_out", summary.left_out}}
                   .dump()
            << std::endl;
}

}  // namespace

void AddReportCommand(CLI::App& parent) {
  auto args = std::make_shared<ReportRequest>();
  CLI::App* command = parent.add_subcommand(
      "report",
      "Table I (violations over the first K agent steps, mean and std over seeds, with the "
      "paper's numbers) and learning curves of a sweep, as Markdown, CSV, PNG and SVG");
  command
      ->add_option("folders", args->sweep_dirs,
                   "sweep directories, or report directories (their run-logs/), one or more; or "
                   "one experiment folder (experiments/<name>): its runs and its report's logs, "
                   "reported into experiments/<name>/report over its window")
      ->required()
      ->check(ExistingFolder());
  command->add_flag("--complete", args->complete,
                    "leave out runs that have not reached the window yet (named in the report)");
  command->add_option("--out", args->out, "report directory (without an experiment)");
  command
      ->add_option("--window", args->window,
                   "K: agent steps counted in Table I (default: the smallest run budget, at "
                   "most 10000)")
      ->check(IntegerIn(1, kMaxSteps));
  command
      ->add_option("--reference", args->reference,
                   "folder of the original's logs (default: data/reference of the source tree)")
      ->check(ExistingFolder());
  command
      ->add_option("--earlier-table", args->earlier_tables,
                   "an earlier report's table-1.csv, for cells whose runs' logs are gone: its "
                   "cells of tasks and planners that the runs given do not cover join the table "
                   "(marked †; the original's side made again); one or more, the first holding "
                   "a cell gives it")
      ->check(ExistingFile());
  command
      ->add_option("--grid-step", args->grid_step,
                   "agent steps between curve points (default: the longest run / 50)")
      ->check(IntegerIn(1, kMaxSteps));
  command
      ->add_option("--smoothing", args->smoothing,
                   "agent steps of episodes averaged into each curve point (default: a tenth "
                   "of the longest run)")
      ->check(IntegerIn(1, kMaxSteps));
  command->callback([args, command] {
    ReportRequest chosen = *args;
    if (chosen.sweep_dirs.size() == 1 && IsExperimentDir(chosen.sweep_dirs.front())) {
      for (const char* option : {"--out", "--window", "--earlier-table", "--complete"}) {
        Require(command->count(option) == 0,
                "{} is fixed by the experiment '{}' ({}): give no {} with an experiment", option,
                chosen.sweep_dirs.front(), kExperimentFile, option);
      }
      const Experiment experiment = LoadExperiment(chosen.sweep_dirs.front());
      chosen.experiment = StampOf(experiment);
      chosen.check_runs = [experiment](const std::vector<RunRecord>& runs) {
        CheckRunsAgainstExperiment(runs, experiment);
      };
      chosen.sweep_dirs.clear();
      for (const fs::path& dir : {experiment.runs_dir(), experiment.report_dir()}) {
        if (fs::is_directory(dir)) chosen.sweep_dirs.push_back(dir.string());
      }
      Require(!chosen.sweep_dirs.empty(), "the experiment '{}' has no runs yet: start them with "
              "`cmbrl sweep {}`", experiment.name, experiment.dir.string());
      chosen.out = experiment.report_dir().string();
      chosen.window = experiment.window;
      chosen.complete = true;  // a run short of the window is named, not counted
    }
    Require(!chosen.out.empty(), "--out REPORT_DIR is required (or give an experiment folder)");
    RunReport(chosen);
  });
}

}  // namespace cmbrl::app

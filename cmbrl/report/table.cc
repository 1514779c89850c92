#include "cmbrl/report/table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "cmbrl/core/check.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/planning/planning_options.h"
#include "cmbrl/report/reference.h"
#include "cmbrl/report/statistics.h"
#include "cmbrl/run/algorithms.h"
#include "cmbrl/run/progress_table.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

// The original's columns of a cell (its task and planner set) from its logs over the window;
// left empty where a log of the cell stops before the window's end.
void FillOriginalSide(const std::vector<RunRecord>& reference, std::int64_t window,
                      TableCell& cell) {
  const std::vector<const RunRecord*> original =
      ReferenceRunsOf(reference, cell.task, cell.planner);
  const bool covered = std::all_of(original.begin(), original.end(),
                                   [&](const RunRecord* r) { return StepsReached(*r) >= window; });
  if (covered) {
    for (const RunRecord* run : original) {
      cell.original_per_seed.push_back(ViolationsWithin(*run, window));
      cell.original_final_returns.push_back(FinalReturn(*run, window));
      if (!run->epoch_log) {
        cell.original_heavy_episodes.push_back(HeavyEpisodesWithin(*run, window));
      }
    }
  }
  for (const RunRecord* run : original) {
    if (const auto first = FirstEpochOf(*run)) cell.original_first_epochs.push_back(*first);
  }
}

// `mean` against `original`'s range widened by 30% of each end's size (0.7 x the lowest to 1.3 x
// the highest where both are positive): "yes", "no: above N" or, where the lower end counts,
// "no: below N", N with `digits` decimals; "" without values.
std::string AgainstWidenedRange(double mean, const std::vector<double>& original,
                                bool lower_end_counts, int digits) {
  if (original.empty()) return "";
  const auto [low, high] = std::minmax_element(original.begin(), original.end());
  const double lower = *low * (*low >= 0 ? 0.7 : 1.3);
  const double upper = *high * (*high >= 0 ? 1.3 : 0.7);
  if (mean > upper) return fmt::format("no: above {:.{}f}", upper, digits);
  if (lower_end_counts && mean < lower) return fmt::format("no: below {:.{}f}", lower, digits);
  return "yes";
}

}  // namespace

bool IsPapersMethod(const std::string& planner) {
  const PlannerInfo* info = FindPlannerInfoOrNull(planner);
  return info != nullptr && info->is_papers_method;
}

std::optional<double> PaperViolations(const std::string& task, const std::string& planner) {
  // The paper's Table I as data (data/reference/paper-table-1.csv: task, method, violations),
  // read once. Without the file (a report made away from the source tree) no cell has it.
  static const std::map<std::pair<std::string, std::string>, double> table = [] {
    std::map<std::pair<std::string, std::string>, double> cells;
    const fs::path file = fs::path(DefaultReferenceDir()) / "paper-table-1.csv";
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) {
      std::stringstream fields(line);
      std::string task_name, method, count;
      if (!std::getline(fields, task_name, ',') || !std::getline(fields, method, ',') ||
          !std::getline(fields, count)) {
        continue;
      }
      try {
        cells[{task_name, method}] = std::stod(count);
      } catch (const std::exception&) {
        Fail("'{}': line '{}' has no number of violations", file.string(), line);
      }
    }
    return cells;
  }();
  const auto cell = table.find({task, planner});
  if (cell == table.end()) return std::nullopt;
  return cell->second;
}

std::string VersusOriginal(const TableCell& cell) {
  return AgainstRange(cell.mean, cell.original_per_seed);
}

std::string WithinWidenedRange(const TableCell& cell) {
  // For the paper's own method fewer violations are better: only the upper end counts.
  return AgainstWidenedRange(cell.mean, cell.original_per_seed, !IsPapersMethod(cell.planner), 1);
}

std::string ReturnWithinWidenedRange(const TableCell& cell) {
  return AgainstWidenedRange(cell.return_mean, cell.original_final_returns, true, 2);
}

std::vector<TableCell> ViolationTable(const std::vector<RunRecord>& runs, std::int64_t window,
                                      const std::vector<RunRecord>& reference,
                                      const std::vector<std::string>& setting_order) {
  const std::vector<std::string> settings = SettingsInOrder(runs, setting_order);
  std::vector<TableCell> cells;
  for (const std::string& task : TasksInOrder(runs)) {
    for (const std::string& planner : MethodsInOrder(runs)) {
      for (const std::string& setting : settings) {
        // A run without a finished episode yet (just started) has nothing to say: counted, it
        // would add a seed with no violations and no return.
        std::vector<const RunRecord*> members;
        for (const RunRecord& run : runs) {
          if (run.config.task == task && MethodOf(run.config) == planner &&
              SettingOf(run) == setting && !run.episodes.empty()) {
            members.push_back(&run);
          }
        }
        if (members.empty()) continue;
        std::sort(members.begin(), members.end(), [](const RunRecord* a, const RunRecord* b) {
          return a->config.seed < b->config.seed;
        });
        for (size_t i = 1; i < members.size(); ++i) {
          const RunRecord& a = *members[i - 1];
          const RunRecord& b = *members[i];
          Require(a.config.seed != b.config.seed,
                  "'{}' and '{}' are both seed {} of one cell ({}, {}): a cell holds one run a "
                  "seed; report them apart, or leave one out",
                  a.source.string(), b.source.string(), b.config.seed, WithSetting(task, setting),
                  MethodLabel(planner));
        }
        TableCell cell;
        cell.task = task;
        cell.planner = planner;
        cell.setting = setting;
        cell.fewest_steps = std::numeric_limits<std::int64_t>::max();
        for (const RunRecord* run : members) {
          cell.seeds.push_back(run->config.seed);
          cell.epoch_log = run->epoch_log;
          cell.per_seed.push_back(ViolationsWithin(*run, window));
          cell.final_returns.push_back(FinalReturn(*run, window));
          // An epoch's mean cost is not an episode's: no count of heavy episodes for epoch logs.
          if (!run->epoch_log) cell.heavy_episodes.push_back(HeavyEpisodesWithin(*run, window));
          cell.feasible_fractions.push_back(FeasibleFractionWithin(*run, window));
          cell.fewest_steps = std::min(cell.fewest_steps, StepsReached(*run));
          if (const auto first = FirstEpochOf(*run)) cell.first_epochs.push_back(*first);
          const double seconds = SecondsTaken(*run);
          if (std::isfinite(seconds)) {
            cell.run_minutes.push_back(seconds / 60.0);
            cell.run_core_minutes.push_back(CoreSecondsTaken(*run) / 60.0);
          }
          const double cpu_seconds = CpuSecondsTaken(*run);
          if (std::isfinite(cpu_seconds)) cell.run_cpu_minutes.push_back(cpu_seconds / 60.0);
          if (const auto causes = ViolationCausesWithin(*run, window)) {
            cell.hazard_steps.push_back(causes->hazard_steps);
            cell.vase_steps.push_back(causes->vase_steps);
          }
        }
        if (cell.run_minutes.size() != members.size()) {
          cell.run_minutes.clear();
          cell.run_core_minutes.clear();
        }
        if (cell.run_cpu_minutes.size() != members.size()) cell.run_cpu_minutes.clear();
        if (cell.hazard_steps.size() != members.size()) {
          cell.hazard_steps.clear();
          cell.vase_steps.clear();
        }
        cell.mean = Mean(cell.per_seed);
        cell.std = SampleStd(cell.per_seed);
        cell.return_mean = Mean(cell.final_returns);
        cell.return_std = SampleStd(cell.final_returns);
        cell.paper = PaperViolations(task, planner);
        FillOriginalSide(reference, window, cell);
        cells.push_back(cell);
      }
    }
  }
  return cells;
}

std::string WithSetting(const std::string& name, const std::string& setting) {
  return setting.empty() ? name : fmt::format("{} ({})", name, setting);
}

std::string AgainstRange(double mean, const std::vector<double>& original) {
  if (original.empty() || !std::isfinite(mean)) return "";
  const auto [low, high] = std::minmax_element(original.begin(), original.end());
  return mean < *low ? "below" : mean > *high ? "above" : "inside";
}

std::string TableCsv(const std::vector<TableCell>& cells, std::int64_t window) {
  std::string text =
      "task,planner,setting,window,seeds,mean,std,per_seed,paper,fewest_steps,return_mean,return_"
      "std,"
      "original_per_seed,original_mean,versus_original,original_return_mean,heavy_per_seed,"
      "feasible_fraction,original_heavy_per_seed,reproduces,return_reproduces,"
      "first_epoch_violations_per_seed,"
      "first_epoch_return_per_seed,original_first_epoch_violations_per_seed,"
      "original_first_epoch_return_per_seed,hazard_steps_per_seed,vase_steps_per_seed,source\n";
  const auto first_epoch_columns = [](const std::vector<FirstEpoch>& epochs) {
    std::vector<std::string> violations, returns;
    for (const FirstEpoch& epoch : epochs) {
      violations.push_back(fmt::format("{}", epoch.violations));
      returns.push_back(fmt::format("{}", epoch.mean_return));
    }
    return fmt::format("{},{}", fmt::join(violations, " "), fmt::join(returns, " "));
  };
  for (const TableCell& cell : cells) {
    const bool original = !cell.original_per_seed.empty();
    text += fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
        cell.task, cell.planner, cell.setting, window, cell.per_seed.size(), cell.mean, cell.std,
        fmt::join(cell.per_seed, " "), cell.paper ? fmt::format("{}", *cell.paper) : "",
        cell.fewest_steps, cell.return_mean, cell.return_std,
        fmt::join(cell.original_per_seed, " "),
        original ? fmt::format("{}", Mean(cell.original_per_seed)) : "", VersusOriginal(cell),
        original ? fmt::format("{}", Mean(cell.original_final_returns)) : "",
        fmt::join(cell.heavy_episodes, " "), ProgressNumber(Mean(cell.feasible_fractions)),
        fmt::join(cell.original_heavy_episodes, " "), WithinWidenedRange(cell),
        ReturnWithinWidenedRange(cell), first_epoch_columns(cell.first_epochs),
        first_epoch_columns(cell.original_first_epochs), fmt::join(cell.hazard_steps, " "),
        fmt::join(cell.vase_steps, " "), cell.source);
  }
  return text;
}

std::vector<TableCell> ReadEarlierTable(const std::string& path, std::int64_t window,
                                        const std::vector<RunRecord>& reference) {
  Require(path.find(',') == std::string::npos,
          "earlier table '{}': expected a path without commas (table-1.csv names it in a column)",
          path);
  const ProgressTable table = ProgressTable::Read(path);
  const std::string expected = "a table-1.csv written by cmbrl report";
  const size_t task = table.Column("task", expected);
  const size_t planner = table.Column("planner", expected);
  const size_t table_window = table.Column("window", expected);
  const size_t per_seed = table.Column("per_seed", expected);
  const size_t fewest_steps = table.Column("fewest_steps", expected);
  const size_t return_mean = table.Column("return_mean", expected);
  const size_t return_std = table.Column("return_std", expected);
  const size_t heavy = table.Column("heavy_per_seed", expected);
  const size_t feasible = table.Column("feasible_fraction", expected);
  // Columns added later: an older table has no violation causes and no source.
  const bool has_causes =
      table.HasColumn("hazard_steps_per_seed") && table.HasColumn("vase_steps_per_seed");
  const size_t hazards = has_causes ? table.Column("hazard_steps_per_seed", expected) : 0;
  const size_t vases = has_causes ? table.Column("vase_steps_per_seed", expected) : 0;
  const bool has_source = table.HasColumn("source");
  const bool has_setting = table.HasColumn("setting");  // added with experiments' axes
  const size_t setting_column = has_setting ? table.Column("setting", expected) : 0;
  const size_t source_column = has_source ? table.Column("source", expected) : 0;
  const auto counts = [&](size_t row, size_t column) {
    std::vector<int> values;
    for (const double v : table.Numbers(row, column)) values.push_back(static_cast<int>(v));
    return values;
  };
  std::vector<TableCell> cells;
  for (size_t row = 0; row < table.rows(); ++row) {
    Require(table.Number(row, table_window) == static_cast<double>(window),
            "{} line {}: window {}: expected the report's window, {} agent steps (an earlier "
            "cell must count the same steps)",
            path, table.line(row), table.Text(row, table_window), window);
    TableCell cell;
    cell.task = table.Text(row, task);
    cell.planner = table.Text(row, planner);
    cell.setting = has_setting ? table.Text(row, setting_column) : "";
    cell.per_seed = table.Numbers(row, per_seed);
    Require(!cell.per_seed.empty(), "{} line {}: per_seed is empty: expected a count per seed",
            path, table.line(row));
    cell.mean = Mean(cell.per_seed);
    cell.std = SampleStd(cell.per_seed);
    cell.paper = PaperViolations(cell.task, cell.planner);
    cell.fewest_steps = static_cast<std::int64_t>(table.Number(row, fewest_steps));
    cell.return_mean = table.Number(row, return_mean);
    cell.return_std = table.Number(row, return_std);
    cell.heavy_episodes = counts(row, heavy);
    cell.feasible_fractions = {table.Number(row, feasible)};
    if (has_causes) {
      cell.hazard_steps = counts(row, hazards);
      cell.vase_steps = counts(row, vases);
    }
    const std::string source = has_source ? table.Text(row, source_column) : "";
    cell.source = source.empty() ? path : source;
    FillOriginalSide(reference, window, cell);
    cells.push_back(cell);
  }
  return cells;
}

std::vector<TableCell> WithEarlierCells(std::vector<TableCell> cells,
                                        const std::vector<TableCell>& earlier) {
  if (earlier.empty()) return cells;  // in ViolationTable's order, a declared one included
  const auto has = [&](const TableCell& cell) {
    return std::any_of(cells.begin(), cells.end(), [&](const TableCell& c) {
      return c.task == cell.task && c.planner == cell.planner && c.setting == cell.setting;
    });
  };
  for (const TableCell& cell : earlier) {
    if (!has(cell)) cells.push_back(cell);
  }
  const auto rank = [](const std::vector<std::string>& known, const std::string& value) {
    return std::find(known.begin(), known.end(), value) - known.begin();
  };
  const std::vector<std::string> tasks = EnvNames();
  const std::vector<std::string> methods = MethodNames();
  std::stable_sort(cells.begin(), cells.end(), [&](const TableCell& a, const TableCell& b) {
    const auto key_a = std::make_pair(rank(tasks, a.task), rank(methods, a.planner));
    const auto key_b = std::make_pair(rank(tasks, b.task), rank(methods, b.planner));
    return key_a != key_b ? key_a < key_b : NaturalLess(a.setting, b.setting);
  });
  return cells;
}

}  // namespace cmbrl

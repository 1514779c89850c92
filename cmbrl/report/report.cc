#include "cmbrl/report/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "cmbrl/core/check.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/learners/mpc/mpc_progress_columns.h"
#include "cmbrl/planning/planning_options.h"
#include "cmbrl/report/reference.h"
#include "cmbrl/run/progress_table.h"
#include "cmbrl/run/run_directory.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

// Per-seed counts for people: whole numbers as such, interpolated ones (model-free epoch logs)
// to one decimal.
std::string Counts(const std::vector<double>& values) {
  std::vector<std::string> texts;
  for (const double v : values) {
    texts.push_back(v == std::round(v) ? fmt::format("{:.0f}", v) : fmt::format("{:.1f}", v));
  }
  return fmt::format("{}", fmt::join(texts, ", "));
}

// A figure with `digits` decimals, or "-" where there is none (NaN).
std::string Figure(double value, int digits) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, digits) : "-";
}

// Counts joined by ", ", or "-" where there are none.
std::string CountsOrDash(const std::vector<int>& counts) {
  return counts.empty() ? "-" : fmt::format("{}", fmt::join(counts, ", "));
}

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

double SampleStd(const std::vector<double>& values) {
  if (values.size() < 2) return 0.0;
  const double mean = Mean(values);
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return std::sqrt(squares / static_cast<double>(values.size() - 1));
}

// The distinct values of a field over the runs, in the order of `known` (the registries'
// order: the paper's), unknown values last.
template <typename Get>
std::vector<std::string> InOrder(const std::vector<RunRecord>& runs, Get get,
                                 const std::vector<std::string>& known) {
  std::vector<std::string> order;
  for (const RunRecord& run : runs) {
    const std::string value = get(run);
    if (std::find(order.begin(), order.end(), value) == order.end()) order.push_back(value);
  }
  const auto rank = [&](const std::string& value) {
    return std::find(known.begin(), known.end(), value) - known.begin();
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
  return order;
}

// Whether `a` sorts before `b` with the numbers in them compared by value ("gamma=0.9" before
// "gamma=0.98", "population=100" before "population=500"): an experiment's settings in order.
bool NaturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      char* a_end = nullptr;
      char* b_end = nullptr;
      const double x = std::strtod(a.c_str() + i, &a_end);
      const double y = std::strtod(b.c_str() + j, &b_end);
      if (x != y) return x < y;
      i = static_cast<size_t>(a_end - a.c_str());
      j = static_cast<size_t>(b_end - b.c_str());
      continue;
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i;
    ++j;
  }
  return a.size() - i < b.size() - j;
}

// A run's setting: its values of an experiment's axes, read from its name (SweepRunName).
std::string SettingOf(const RunRecord& run) {
  return SettingOfRunName(run.name, run.config.task, MethodOf(run.config), run.config.seed);
}

// The runs' distinct settings in natural order ("" first: runs of no axes).
std::vector<std::string> SettingsInOrder(const std::vector<RunRecord>& runs) {
  std::vector<std::string> settings;
  for (const RunRecord& run : runs) settings.push_back(SettingOf(run));
  std::sort(settings.begin(), settings.end(), NaturalLess);
  settings.erase(std::unique(settings.begin(), settings.end()), settings.end());
  return settings;
}

// A cell's row label: its task, with its setting where it has one.
std::string RowLabel(const TableCell& cell) { return WithSetting(cell.task, cell.setting); }

// The first epochs' violations and mean returns, each as "mean (per seed)", or "-" for none.
struct FirstEpochTexts {
  std::string violations, returns;
};
FirstEpochTexts DescribeFirstEpochs(const std::vector<FirstEpoch>& epochs) {
  if (epochs.empty()) return {"-", "-"};
  std::vector<double> violations, returns;
  std::vector<std::string> return_texts;
  for (const FirstEpoch& epoch : epochs) {
    violations.push_back(epoch.violations);
    returns.push_back(epoch.mean_return);
    return_texts.push_back(fmt::format("{:.1f}", epoch.mean_return));
  }
  return {fmt::format("{:.1f} ({})", Mean(violations), Counts(violations)),
          fmt::format("{:.1f} ({})", Mean(returns), fmt::join(return_texts, ", "))};
}

bool IsPapersMethod(const std::string& planner) {
  const PlannerInfo* info = FindPlannerInfoOrNull(planner);
  return info != nullptr && info->is_papers_method;
}

}  // namespace

namespace {

// A row's value of a column that must lie in [low, high] (finite), named in the error.
double InDomain(const ProgressTable& table, const std::string& file, size_t row, size_t column,
                double low, double high, const char* expected) {
  const double value = table.Number(row, column);
  Require(std::isfinite(value) && value >= low && value <= high,
          "{} line {}: {} is {}: expected {}", file, table.line(row), table.header().at(column),
          table.Text(row, column), expected);
  return value;
}

// The same for a count of steps in an episode of `steps` steps: a whole number in [0, steps].
double StepCount(const ProgressTable& table, const std::string& file, size_t row, size_t column,
                 double steps) {
  const double value = InDomain(table, file, row, column, 0.0, steps,
                                "a whole count from 0 to the episode's steps");
  Require(value == std::round(value), "{} line {}: {} is {}: expected a whole count",
          file, table.line(row), table.header().at(column), table.Text(row, column));
  return value;
}

// The same for a column where NaN means "not measured" (a fraction not logged, the means of an
// epoch in which no episode ended): NaN passes, any other value must lie in [low, high].
double NanOrInDomain(const ProgressTable& table, const std::string& file, size_t row,
                     size_t column, double low, double high, const char* expected) {
  const double value = table.Number(row, column);
  return std::isnan(value) ? value : InDomain(table, file, row, column, low, high, expected);
}

std::optional<size_t> RowLimit(std::optional<std::int64_t> rows) {
  if (!rows) return std::nullopt;
  return static_cast<size_t>(std::max<std::int64_t>(*rows, 0));
}

constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace

std::vector<EpisodePoint> ReadProgressEpisodes(const std::string& file,
                                               std::optional<std::int64_t> rows) {
  return ReadEpisodeColumns(file, /*has_steps=*/true, rows);
}

std::vector<EpisodePoint> ReadEpisodeColumns(const std::string& file, bool has_steps,
                                             std::optional<std::int64_t> rows) {
  const ProgressTable table = ProgressTable::Read(file, RowLimit(rows));
  const std::string expected =
      fmt::format("a progress log with {}, {}, {}{}", kEpRetColumn, kEpCostColumn,
                  kTotalEnvInteractsColumn, has_steps ? fmt::format(" and {}", kStepsColumn) : "");
  const size_t ret = table.Column(kEpRetColumn, expected);
  const size_t cost = table.Column(kEpCostColumn, expected);
  const size_t total = table.Column(kTotalEnvInteractsColumn, expected);
  const size_t steps = has_steps ? table.Column(kStepsColumn, expected) : 0;
  const bool has_feasible = table.HasColumn(kFeasibleFractionColumn);
  const size_t feasible = has_feasible ? table.Column(kFeasibleFractionColumn, expected) : 0;
  const bool has_causes =
      table.HasColumn(kHazardStepsColumn) && table.HasColumn(kVaseStepsColumn);
  const size_t hazards = has_causes ? table.Column(kHazardStepsColumn, expected) : 0;
  const size_t vases = has_causes ? table.Column(kVaseStepsColumn, expected) : 0;
  std::vector<EpisodePoint> episodes;
  for (size_t row = 0; row < table.rows(); ++row) {
    EpisodePoint point;
    const std::int64_t previous = episodes.empty() ? 0 : episodes.back().end_step;
    point.end_step = static_cast<std::int64_t>(
        InDomain(table, file, row, total, static_cast<double>(previous), kInfinity,
                 "a count of steps that never falls"));
    point.steps = has_steps
                      ? static_cast<int>(InDomain(table, file, row, steps, 0.0,
                                                  static_cast<double>(point.end_step - previous),
                                                  "the episode's steps, at most the rise of "
                                                  "TotalEnvInteracts"))
                      : static_cast<int>(point.end_step - previous);
    point.episode_return =
        InDomain(table, file, row, ret, -kInfinity, kInfinity, "a finite return");
    point.episode_cost = StepCount(table, file, row, cost, point.steps);
    if (has_feasible) {
      point.feasible_fraction =
          NanOrInDomain(table, file, row, feasible, 0.0, 1.0, "a fraction from 0 to 1");
    }
    if (has_causes) {
      point.hazard_steps = StepCount(table, file, row, hazards, point.steps);
      point.vase_steps = StepCount(table, file, row, vases, point.steps);
    }
    point.cumulative_violations =
        (episodes.empty() ? 0.0 : episodes.back().cumulative_violations) + point.episode_cost;
    episodes.push_back(point);
  }
  return episodes;
}

namespace {

// The folders under `parent` that hold a run (config.yaml), in name order.
std::vector<fs::path> RunFolders(const fs::path& parent) {
  std::vector<fs::path> dirs;
  if (!fs::is_directory(parent)) return dirs;
  for (const fs::directory_entry& entry : fs::directory_iterator(parent)) {
    if (entry.is_directory() && RunDirectory(entry.path()).HoldsRun()) dirs.push_back(entry.path());
  }
  std::sort(dirs.begin(), dirs.end());
  return dirs;
}

// A run's record; `rows` limits it to the progress rows its checkpoint covers.
RunRecord ReadRunRecord(const fs::path& dir, std::optional<std::int64_t> rows) {
  const RunDirectory run_dir(dir);
  RunRecord run;
  run.name = dir.filename().string();
  run.source = dir;
  run.config = LoadTrainConfig(run_dir.config_file().string());
  const LearnerFamily family = FindAlgorithm(run.config.algorithm).family;
  run.epoch_log = family != LearnerFamily::kMpc;
  run.episodes = EpisodeReaderOf(family)(run_dir.progress_file().string(), rows);
  run.sessions = ReadRunSessions(run_dir);
  return run;
}

// Whether `log`'s points are the first points of `run` (a report's copy of a run that went on).
bool IsPrefixOf(const RunRecord& log, const RunRecord& run) {
  if (log.epoch_log != run.epoch_log || log.episodes.size() > run.episodes.size()) return false;
  for (size_t i = 0; i < log.episodes.size(); ++i) {
    const EpisodePoint& a = log.episodes[i];
    const EpisodePoint& b = run.episodes[i];
    if (a.end_step != b.end_step || a.episode_cost != b.episode_cost ||
        a.episode_return != b.episode_return) {
      return false;
    }
  }
  return true;
}

constexpr const char* kLogsFolder = "run-logs";

}  // namespace

std::vector<RunRecord> ReadSweeps(const std::vector<std::string>& sweep_dirs) {
  std::map<std::string, std::pair<RunRecord, bool>> found;  // name -> (run, read from a log)
  const auto add = [&](RunRecord run, bool is_log) {
    const auto it = found.find(run.name);
    if (it == found.end()) {
      const std::string name = run.name;
      found.emplace(name, std::make_pair(std::move(run), is_log));
      return;
    }
    RunRecord& kept = it->second.first;
    const bool kept_is_log = it->second.second;
    if (kept_is_log != is_log) {
      const RunRecord& log = kept_is_log ? kept : run;
      const RunRecord& live = kept_is_log ? run : kept;
      if (IsPrefixOf(log, live)) {
        if (kept_is_log) it->second = std::make_pair(std::move(run), false);
        return;
      }
    }
    throw Error(fmt::format(
        "run '{}' is in both '{}' and '{}' and neither is a report's log of the other: expected "
        "each run once (leave one folder out)",
        run.name, kept.source.string(), run.source.string()));
  };
  for (const std::string& sweep_dir : sweep_dirs) {
    const fs::path runs_dir = fs::path(sweep_dir) / "runs";
    const fs::path logs_dir = fs::path(sweep_dir) / kLogsFolder;
    Require(fs::is_directory(runs_dir) || fs::is_directory(logs_dir),
            "'{}' holds neither runs/ nor run-logs/: expected a cmbrl sweep or report folder",
            sweep_dir);
    for (const fs::path& dir : RunFolders(runs_dir)) {
      // A run whose progress.csv disagrees with its checkpoint's manifest is refused, naming the
      // file; rows written after the last checkpoint (a run in progress, or added by hand) are
      // left out.
      // A run in progress may swap its checkpoint while this reads it: a second look settles it.
      const RunDirectory run_dir(dir);
      std::optional<CheckpointManifest> checkpoint;
      try {
        checkpoint = VerifiedCheckpoint(run_dir, /*files=*/false);
      } catch (const Error&) {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        checkpoint = VerifiedCheckpoint(run_dir, /*files=*/false);
      }
      // Only what the checkpoint covers: rows after it are not part of the run's record.
      add(ReadRunRecord(dir, checkpoint ? checkpoint->rows : 0), /*is_log=*/false);
    }
    // A report's logs have no checkpoint to check them against: they are what was reported.
    for (const fs::path& dir : RunFolders(logs_dir)) {
      add(ReadRunRecord(dir, std::nullopt), /*is_log=*/true);
    }
  }
  std::vector<RunRecord> runs;
  std::map<std::string, fs::path> by_id;  // run id -> the folder it was read from
  for (auto& [name, entry] : found) {
    const std::string id = RunIdOf(entry.first.sessions);
    if (!id.empty()) {
      const auto [it, first] = by_id.emplace(id, entry.first.source);
      Require(first,
              "'{}' and '{}' hold one run (run id {} in their sessions.jsonl): a run folder "
              "copied or moved counts once; remove the copy",
              it->second.string(), entry.first.source.string(), id);
    }
    runs.push_back(std::move(entry.first));
  }
  return runs;
}

std::vector<RunRecord> ReadSweep(const std::string& sweep_dir) { return ReadSweeps({sweep_dir}); }

void KeepRunLogs(const std::vector<RunRecord>& runs, const std::string& out) {
  const fs::path logs = fs::path(out) / kLogsFolder;
  const fs::path staging = fs::path(out) / (std::string(kLogsFolder) + ".new");
  const RunDirectory layout("");
  const std::set<std::string> log_files = {layout.config_file().filename().string(),
                                           layout.progress_file().filename().string(),
                                           layout.sessions_file().filename().string()};
  // Only what an earlier report wrote is replaced; anything else there is not ours to delete.
  for (const fs::path& folder : {logs, staging}) {
    if (!fs::exists(folder)) continue;
    for (const fs::directory_entry& run : fs::directory_iterator(folder)) {
      Require(run.is_directory(), "'{}' holds '{}': expected only run logs kept by cmbrl report",
              folder.string(), run.path().string());
      for (const fs::directory_entry& file : fs::directory_iterator(run.path())) {
        Require(log_files.count(file.path().filename().string()) == 1,
                "'{}' holds '{}': expected only run logs (config.yaml, progress.csv and "
                "sessions.jsonl) kept by cmbrl report",
                folder.string(), file.path().string());
      }
    }
  }
  fs::remove_all(staging);
  for (const RunRecord& run : runs) {
    const RunDirectory from(run.source);
    const RunDirectory to(staging / run.name);
    std::error_code error;
    fs::create_directories(to.root(), error);
    for (const auto& [source, target] :
         {std::make_pair(from.config_file(), to.config_file()),
          std::make_pair(from.progress_file(), to.progress_file()),
          std::make_pair(from.sessions_file(), to.sessions_file())}) {
      if (source == from.sessions_file() && !fs::exists(source)) continue;  // an older run
      if (!error) fs::copy_file(source, target, error);
      Require(!error, "could not copy '{}' to '{}': {}", source.string(), target.string(),
              error.message());
    }
  }
  fs::remove_all(logs);
  fs::rename(staging, logs);
}

std::int64_t StepsReached(const RunRecord& run) {
  return run.episodes.empty() ? 0 : run.episodes.back().end_step;
}

std::vector<std::string> LeaveOutRunsShortOf(std::vector<RunRecord>& runs, std::int64_t window) {
  std::vector<std::string> left_out;
  std::vector<RunRecord> kept;
  for (RunRecord& run : runs) {
    if (StepsReached(run) < window) {
      left_out.push_back(fmt::format("{} ({} steps)", run.name, StepsReached(run)));
    } else {
      kept.push_back(std::move(run));
    }
  }
  runs = std::move(kept);
  return left_out;
}

double ViolationsWithin(const RunRecord& run, std::int64_t window) {
  if (!run.epoch_log) {
    double violations = 0.0;
    for (const EpisodePoint& episode : run.episodes) {
      if (episode.end_step <= window) violations += episode.episode_cost;
    }
    return violations;
  }
  double before = 0.0;
  std::int64_t before_step = 0;
  for (const EpisodePoint& epoch : run.episodes) {
    if (epoch.end_step >= window) {
      const double share = static_cast<double>(window - before_step) /
                           static_cast<double>(epoch.end_step - before_step);
      return before + share * (epoch.cumulative_violations - before);
    }
    before = epoch.cumulative_violations;
    before_step = epoch.end_step;
  }
  return before;
}

EpisodeReader EpisodeReaderOf(LearnerFamily family) {
  switch (family) {
    case LearnerFamily::kMpc:
      return ReadProgressEpisodes;
    case LearnerFamily::kPolicyOptimisation:
      return ReadEpochLog;
  }
  Fail("no episode reader for this learner family");
}

std::vector<EpisodePoint> ReadEpochLog(const std::string& file,
                                       std::optional<std::int64_t> rows) {
  const ProgressTable table = ProgressTable::Read(file, RowLimit(rows));
  const std::string expected =
      "a model-free progress log with AverageEpRet, AverageEpCost, CumulativeCost and "
      "TotalEnvInteracts";
  const size_t ret = table.Column("AverageEpRet", expected);
  const size_t cost = table.Column("AverageEpCost", expected);
  const size_t cumulative = table.Column("CumulativeCost", expected);
  const size_t total = table.Column("TotalEnvInteracts", expected);
  std::vector<EpisodePoint> epochs;
  for (size_t row = 0; row < table.rows(); ++row) {
    EpisodePoint point;
    const std::int64_t previous = epochs.empty() ? 0 : epochs.back().end_step;
    const double before = epochs.empty() ? 0.0 : epochs.back().cumulative_violations;
    point.end_step = static_cast<std::int64_t>(table.Number(row, total));
    Require(point.end_step > previous,
            "{} line {}: TotalEnvInteracts {} after {}: expected a count that rises", file,
            table.line(row), point.end_step, previous);
    point.steps = static_cast<int>(point.end_step - previous);
    // An epoch in which no episode ended logs NaN for both means (nothing to average).
    point.episode_return = NanOrInDomain(table, file, row, ret, -kInfinity, kInfinity,
                                         "a finite mean return (or nan: no episode ended)");
    point.episode_cost = NanOrInDomain(table, file, row, cost, 0.0, kInfinity,
                                       "a finite mean cost of 0 or more (or nan: no episode ended)");
    point.cumulative_violations =
        InDomain(table, file, row, cumulative, before, before + point.steps,
                 "a running count that rises by at most the epoch's steps");
    epochs.push_back(point);
  }
  return epochs;
}

int HeavyEpisodesWithin(const RunRecord& run, std::int64_t window) {
  int heavy = 0;
  for (const EpisodePoint& episode : run.episodes) {
    heavy += episode.end_step <= window && episode.episode_cost >= kHeavyEpisodeCost;
  }
  return heavy;
}

double FeasibleFractionWithin(const RunRecord& run, std::int64_t window) {
  std::vector<double> fractions;
  for (const EpisodePoint& episode : run.episodes) {
    if (episode.end_step <= window) fractions.push_back(episode.feasible_fraction);
  }
  return fractions.empty() ? std::numeric_limits<double>::quiet_NaN() : Mean(fractions);
}

std::optional<ViolationCauses> ViolationCausesWithin(const RunRecord& run, std::int64_t window) {
  if (run.epoch_log) return std::nullopt;
  ViolationCauses causes;
  for (const EpisodePoint& episode : run.episodes) {
    if (episode.end_step > window) continue;
    if (!std::isfinite(episode.hazard_steps) || !std::isfinite(episode.vase_steps)) {
      return std::nullopt;
    }
    causes.hazard_steps += static_cast<int>(episode.hazard_steps);
    causes.vase_steps += static_cast<int>(episode.vase_steps);
  }
  return causes;
}

double FinalReturn(const RunRecord& run, std::int64_t window, int episodes) {
  std::vector<double> returns;
  for (const EpisodePoint& episode : run.episodes) {
    if (episode.end_step <= window) returns.push_back(episode.episode_return);
  }
  // Nothing ended in the window (a model-free epoch is longer than Table I's window): no return.
  if (returns.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t first =
      returns.size() > static_cast<size_t>(episodes) ? returns.size() - episodes : 0;
  return Mean(std::vector<double>(returns.begin() + first, returns.end()));
}

std::optional<FirstEpoch> FirstEpochOf(const RunRecord& run) {
  const int episodes = run.config.training.episodes_per_epoch;
  if (run.epoch_log || episodes <= 0 || run.episodes.size() < static_cast<size_t>(episodes)) {
    return std::nullopt;
  }
  FirstEpoch first;
  first.episodes = episodes;
  for (int i = 0; i < episodes; ++i) {
    first.violations += run.episodes[static_cast<size_t>(i)].episode_cost;
    first.mean_return += run.episodes[static_cast<size_t>(i)].episode_return;
  }
  first.mean_return /= episodes;
  return first;
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
  if (cell.original_per_seed.empty()) return "";
  const auto [low, high] =
      std::minmax_element(cell.original_per_seed.begin(), cell.original_per_seed.end());
  const double upper = 1.3 * *high;
  const double lower = 0.7 * *low;
  if (cell.mean > upper) return fmt::format("no: above {:.1f}", upper);
  if (cell.mean < lower && !IsPapersMethod(cell.planner)) {
    return fmt::format("no: below {:.1f}", lower);
  }
  return "yes";
}

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

}  // namespace

std::vector<TableCell> ViolationTable(const std::vector<RunRecord>& runs, std::int64_t window,
                                      const std::vector<RunRecord>& reference) {
  const auto task_of = [](const RunRecord& r) { return r.config.task; };
  const auto planner_of = [](const RunRecord& r) { return MethodOf(r.config); };
  const std::vector<std::string> settings = SettingsInOrder(runs);
  std::vector<TableCell> cells;
  for (const std::string& task : InOrder(runs, task_of, EnvNames())) {
    for (const std::string& planner : InOrder(runs, planner_of, MethodNames())) {
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
          if (const auto causes = ViolationCausesWithin(*run, window)) {
            cell.hazard_steps.push_back(causes->hazard_steps);
            cell.vase_steps.push_back(causes->vase_steps);
          }
        }
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

namespace {

// TableMarkdown's sections after Table I and the returns.

// Each cell against the original's seeds over the same window ("" without them).
std::string OriginalComparisonMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  if (std::none_of(cells.begin(), cells.end(),
                   [](const TableCell& c) { return !c.original_per_seed.empty(); })) {
    return "";
  }
  std::string text = fmt::format(
      "\nAgainst the original's own logs over the same {} steps (its seeds 0, 10 and 100; "
      "data/reference/): where our mean lies against its seeds' range; whether it reproduces "
      "the original, that is lies within that range widened by 30% (0.7 x its lowest seed to "
      "1.3 x its highest; for MPC-RCE, the paper's method, only the upper end counts); and the "
      "return of the last 10 episodes.\n\n"
      "| task | method | ours (per seed) | original (per seed) | ours vs its range | "
      "reproduces | return, ours | return, original | episodes with >= 20, ours | the "
      "original's | feasible fraction, ours |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
      window);
  for (const TableCell& cell : cells) {
    if (cell.original_per_seed.empty()) continue;
    text += fmt::format(
        "| {} | {} | {:.1f} ({}) | {:.1f} ({}) | {} | {} | {} | {} | {} | {} | {} |\n",
        RowLabel(cell), MethodLabel(cell.planner), cell.mean, Counts(cell.per_seed),
        Mean(cell.original_per_seed), Counts(cell.original_per_seed), VersusOriginal(cell),
        WithinWidenedRange(cell), Figure(cell.return_mean, 2),
        Figure(Mean(cell.original_final_returns), 2), CountsOrDash(cell.heavy_episodes),
        CountsOrDash(cell.original_heavy_episodes), Figure(Mean(cell.feasible_fractions), 3));
  }
  return text;
}

// The first epochs, ours against the original's ("" where no cell has both).
std::string FirstEpochMarkdown(const std::vector<TableCell>& cells) {
  const bool any_first_epoch = std::any_of(cells.begin(), cells.end(), [](const TableCell& c) {
    return !c.first_epochs.empty() && !c.original_first_epochs.empty();
  });
  if (!any_first_epoch) return "";
  std::string text =
      "\nThe first epoch, the one comparison on equal data: each run's first episodes before "
      "its first refit (10 in the paper's loop), planned with models fitted on the random "
      "pre-training data only, as the original's first 10 were. Their violations (sum) and "
      "return (mean of the episodes), mean over seeds (per seed).\n\n"
      "| task | method | episodes, ours | violations, ours | the original's | return, ours | "
      "the original's |\n|---|---|---|---|---|---|---|\n";
  for (const TableCell& cell : cells) {
    if (cell.first_epochs.empty() || cell.original_first_epochs.empty()) continue;
    std::vector<int> counts;
    for (const FirstEpoch& epoch : cell.first_epochs) {
      if (std::find(counts.begin(), counts.end(), epoch.episodes) == counts.end()) {
        counts.push_back(epoch.episodes);
      }
    }
    const FirstEpochTexts ours = DescribeFirstEpochs(cell.first_epochs);
    const FirstEpochTexts original = DescribeFirstEpochs(cell.original_first_epochs);
    text += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", RowLabel(cell),
                        MethodLabel(cell.planner), fmt::join(counts, ", "), ours.violations,
                        original.violations, ours.returns, original.returns);
  }
  return text;
}

// Where the violations happened, for the cells whose runs logged it ("" where none did).
std::string ViolationCausesMarkdown(const std::vector<TableCell>& cells) {
  if (std::all_of(cells.begin(), cells.end(),
                  [](const TableCell& c) { return c.hazard_steps.empty(); })) {
    return "";
  }
  std::string text =
      "\nWhere the violations happened (runs that log it: HazardSteps and VaseSteps): violating "
      "steps inside a hazard and at a vase (touched, or moving faster than allowed after a "
      "push), per seed. A step can be both.\n\n"
      "| task | method | violating steps | in hazards | at vases |\n|---|---|---|---|---|\n";
  for (const TableCell& cell : cells) {
    if (cell.hazard_steps.empty()) continue;
    text += fmt::format("| {} | {} | {} | {} | {} |\n", RowLabel(cell), MethodLabel(cell.planner),
                        Counts(cell.per_seed), CountsOrDash(cell.hazard_steps),
                        CountsOrDash(cell.vase_steps));
  }
  return text;
}

}  // namespace

namespace {

// The cell of a task, planner and setting, or nullptr when the table has none.
const TableCell* FindCell(const std::vector<TableCell>& cells, const std::string& task,
                          const std::string& planner, const std::string& setting) {
  const auto it = std::find_if(cells.begin(), cells.end(), [&](const TableCell& c) {
    return c.task == task && c.planner == planner && c.setting == setting;
  });
  return it == cells.end() ? nullptr : &*it;
}

// The table's rows: its distinct (task, setting) pairs, in the cells' order.
std::vector<std::pair<std::string, std::string>> TaskSettingRows(
    const std::vector<TableCell>& cells) {
  std::vector<std::pair<std::string, std::string>> rows;
  for (const TableCell& cell : cells) {
    const std::pair<std::string, std::string> row(cell.task, cell.setting);
    if (std::find(rows.begin(), rows.end(), row) == rows.end()) rows.push_back(row);
  }
  return rows;
}

// The distinct values of one field of the cells (task or planner), in the table's order.
std::vector<std::string> DistinctInOrder(const std::vector<TableCell>& cells,
                                         std::string TableCell::*field) {
  std::vector<std::string> values;
  for (const TableCell& cell : cells) {
    if (std::find(values.begin(), values.end(), cell.*field) == values.end()) {
      values.push_back(cell.*field);
    }
  }
  return values;
}

}  // namespace

std::string TableMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  const std::vector<std::string> planners = DistinctInOrder(cells, &TableCell::planner);
  std::string text = fmt::format(
      "Violations during the first {} agent steps: ours as mean ± std over seeds (seeds), the "
      "paper's Table I (mean of 3 seeds over 10,000 steps) in brackets. * marks a cell whose "
      "shortest run stopped before the window's end.\n\n| task |",
      window);
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " |";
  text += "\n|---|";
  for (size_t i = 0; i < planners.size(); ++i) text += "---|";
  text += "\n";
  const std::vector<std::pair<std::string, std::string>> rows = TaskSettingRows(cells);
  for (size_t r = 0; r < rows.size(); ++r) {
    const auto& [task, setting] = rows[r];
    if (r > 0) text += "\n";
    text += "| " + WithSetting(task, setting) + " |";
    for (const std::string& planner : planners) {
      const TableCell* it = FindCell(cells, task, planner, setting);
      if (it == nullptr) {
        text += " |";
        continue;
      }
      text += fmt::format(" {:.1f} ± {:.1f} ({}){}{}", it->mean, it->std, it->per_seed.size(),
                          it->fewest_steps < window ? "*" : "", it->source.empty() ? "" : "†");
      text += it->paper ? fmt::format(" [{:.0f}] |", *it->paper) : " |";
    }
  }
  std::vector<std::string> sources;
  for (const TableCell& cell : cells) {
    if (!cell.source.empty() &&
        std::find(sources.begin(), sources.end(), cell.source) == sources.end()) {
      sources.push_back(cell.source);
    }
  }
  if (!sources.empty()) {
    text += fmt::format(
        "\n\n† read from an earlier report's table ('{}'): its runs' logs are not kept, so the "
        "cell has no curve and no first epoch here.",
        fmt::join(sources, "', '"));
  }
  text +=
      "\n\nReturn at the end of the same window: mean EpRet of each run's last 10 episodes "
      "that ended in it, mean ± std over seeds.\n\n| task |";
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " |";
  text += "\n|---|";
  for (size_t i = 0; i < planners.size(); ++i) text += "---|";
  for (const auto& [task, setting] : rows) {
    text += "\n| " + WithSetting(task, setting) + " |";
    for (const std::string& planner : planners) {
      const TableCell* it = FindCell(cells, task, planner, setting);
      text += it == nullptr ? " |"
              : !std::isfinite(it->return_mean)
                  ? " - |"
                  : fmt::format(" {:.2f} ± {:.2f} |", it->return_mean, it->return_std);
    }
  }
  text += "\n";
  text += OriginalComparisonMarkdown(cells, window);
  text += FirstEpochMarkdown(cells);
  text += ViolationCausesMarkdown(cells);
  return text;
}

MeanInterval BootstrapMeanInterval(const std::vector<double>& values, double level,
                                   int resamples) {
  Require(level > 0.0 && level < 1.0 && resamples >= 1,
          "a bootstrap interval needs a level in (0, 1) and at least one resample: got {} and {}",
          level, resamples);
  MeanInterval interval;
  if (values.empty()) return interval;
  // A fixed seed: the interval is a property of the values, and a report regenerates alike.
  std::mt19937_64 generator(0x5eedb007);
  std::vector<double> means(static_cast<size_t>(resamples));
  for (double& mean : means) {
    double sum = 0.0;
    for (size_t i = 0; i < values.size(); ++i) sum += values[generator() % values.size()];
    mean = sum / static_cast<double>(values.size());
  }
  std::sort(means.begin(), means.end());
  const auto at = [&](double share) {
    const double position = share * static_cast<double>(means.size() - 1);
    return means[static_cast<size_t>(std::lround(position))];
  };
  interval.low = at((1.0 - level) / 2.0);
  interval.high = at(1.0 - (1.0 - level) / 2.0);
  return interval;
}

std::string WithSetting(const std::string& name, const std::string& setting) {
  return setting.empty() ? name : fmt::format("{} ({})", name, setting);
}

std::string AgainstRange(double mean, const std::vector<double>& original) {
  if (original.empty() || !std::isfinite(mean)) return "";
  const auto [low, high] = std::minmax_element(original.begin(), original.end());
  return mean < *low ? "below" : mean > *high ? "above" : "inside";
}

namespace {

// What the cells count in: agent steps and episodes (MPC runs), environment steps and epochs
// (model-free runs), or both named where a table holds both.
struct CountUnits {
  std::string steps, violations, returns;
};
CountUnits UnitsOf(const std::vector<TableCell>& cells) {
  const bool epochs = std::any_of(cells.begin(), cells.end(), [](auto& c) { return c.epoch_log; });
  const bool episodes =
      std::any_of(cells.begin(), cells.end(), [](auto& c) { return !c.epoch_log; });
  const CountUnits mpc{"agent steps", "the EpCost of the episodes that ended in the window",
                       "the mean EpRet of each run's last 10 episodes in it"};
  const CountUnits model_free{"environment steps",
                              "the cumulative cost at the window's end, interpolated in its epoch",
                              "the mean AverageEpRet of each run's last 10 epochs in it"};
  if (!epochs) return mpc;
  if (!episodes) return model_free;
  return {"steps (agent steps for MPC runs, environment steps for model-free ones)",
          mpc.violations + "; for model-free runs " + model_free.violations,
          mpc.returns + "; for model-free runs " + model_free.returns};
}

// "12.3 [8.0, 17.1]": a mean and its bootstrap 90% interval.
std::string MeanWithInterval(const std::vector<double>& values, int digits) {
  if (values.empty()) return "-";
  const MeanInterval interval = BootstrapMeanInterval(values);
  return fmt::format("{} [{}, {}]", Figure(Mean(values), digits), Figure(interval.low, digits),
                     Figure(interval.high, digits));
}

std::string PerSeed(const std::vector<double>& values, int digits) {
  std::vector<std::string> texts;
  for (const double v : values) texts.push_back(Figure(v, digits));
  return texts.empty() ? "-" : fmt::format("{}", fmt::join(texts, ", "));
}

}  // namespace

std::string ProtocolVerdictMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  const std::vector<std::string> planners = DistinctInOrder(cells, &TableCell::planner);
  const CountUnits units = UnitsOf(cells);
  std::string text = fmt::format(
      "Violations during the first {} {}: mean over seeds [bootstrap 90% interval of "
      "the mean]. \"Least\": the paper's method violates least, its interval wholly below every "
      "other method's (\"yes\"), or only its mean lowest (\"mean only\"). Against the "
      "original: where our mean lies against the range of the original's three seeds over the "
      "same window, for violations / for the return ({}).\n\n| task |",
      window, units.steps, units.returns);
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " |";
  text += " least? |";
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " vs original |";
  text += "\n|---|";
  for (size_t i = 0; i < 2 * planners.size() + 1; ++i) text += "---|";
  text += "\n";
  for (const auto& [task, setting] : TaskSettingRows(cells)) {
    text += "| " + WithSetting(task, setting) + " |";
    std::optional<std::string> papers;
    for (const std::string& planner : planners) {
      const TableCell* cell = FindCell(cells, task, planner, setting);
      text += " " + (cell ? MeanWithInterval(cell->per_seed, 1) : std::string("-")) + " |";
      if (cell && IsPapersMethod(planner)) papers = planner;
    }
    std::string verdict = "-";
    if (papers) {
      const TableCell& ours = *FindCell(cells, task, *papers, setting);
      const MeanInterval ours_interval = BootstrapMeanInterval(ours.per_seed);
      bool lowest_mean = true, apart = true, others = false;
      for (const TableCell& other : cells) {
        if (other.task != task || other.setting != setting || other.planner == *papers) continue;
        others = true;
        lowest_mean = lowest_mean && ours.mean < other.mean;
        apart = apart && ours_interval.high < BootstrapMeanInterval(other.per_seed).low;
      }
      if (others) verdict = !lowest_mean ? "no" : apart ? "yes" : "mean only";
    }
    text += " " + verdict + " |";
    for (const std::string& planner : planners) {
      const TableCell* cell = FindCell(cells, task, planner, setting);
      if (cell == nullptr || cell->original_per_seed.empty()) {
        text += " - |";
        continue;
      }
      text += fmt::format(" {} / {} |", AgainstRange(cell->mean, cell->original_per_seed),
                          AgainstRange(cell->return_mean, cell->original_final_returns));
    }
    text += "\n";
  }
  return text;
}

std::string ProtocolCellsMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  const CountUnits units = UnitsOf(cells);
  std::string text = fmt::format(
      "Every cell over the first {} {}: violations ({}) and return ({}), per seed in seed order, "
      "their mean [bootstrap 90% interval], and the original's seeds (0, 10, 100) from its "
      "logs. * marks a cell whose shortest run has not reached the window.\n\n"
      "| task | method | seeds | violations per seed | mean [90%] | original | vs original | "
      "return per seed | mean [90%] | original | vs original |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n",
      window, units.steps, units.violations, units.returns);
  for (const TableCell& cell : cells) {
    const std::string original =
        cell.original_per_seed.empty()
            ? "-"
            : fmt::format("{} ({})", PerSeed(cell.original_per_seed, 0),
                          Figure(Mean(cell.original_per_seed), 1));
    const std::string original_returns =
        cell.original_final_returns.empty()
            ? "-"
            : fmt::format("{} ({})", PerSeed(cell.original_final_returns, 2),
                          Figure(Mean(cell.original_final_returns), 2));
    const std::string vs = AgainstRange(cell.mean, cell.original_per_seed);
    const std::string vs_return = AgainstRange(cell.return_mean, cell.original_final_returns);
    text += fmt::format("| {} | {} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                        RowLabel(cell), MethodLabel(cell.planner), cell.per_seed.size(),
                        cell.fewest_steps < window ? "*" : "", Counts(cell.per_seed),
                        MeanWithInterval(cell.per_seed, 1), original, vs.empty() ? "-" : vs,
                        PerSeed(cell.final_returns, 2), MeanWithInterval(cell.final_returns, 2),
                        original_returns, vs_return.empty() ? "-" : vs_return);
  }
  return text;
}

std::string TableCsv(const std::vector<TableCell>& cells, std::int64_t window) {
  std::string text =
      "task,planner,setting,window,seeds,mean,std,per_seed,paper,fewest_steps,return_mean,return_"
      "std,"
      "original_per_seed,original_mean,versus_original,original_return_mean,heavy_per_seed,"
      "feasible_fraction,original_heavy_per_seed,reproduces,first_epoch_violations_per_seed,"
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
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", cell.task,
        cell.planner, cell.setting, window, cell.per_seed.size(), cell.mean, cell.std,
        fmt::join(cell.per_seed, " "), cell.paper ? fmt::format("{}", *cell.paper) : "",
        cell.fewest_steps, cell.return_mean, cell.return_std,
        fmt::join(cell.original_per_seed, " "),
        original ? fmt::format("{}", Mean(cell.original_per_seed)) : "", VersusOriginal(cell),
        original ? fmt::format("{}", Mean(cell.original_final_returns)) : "",
        fmt::join(cell.heavy_episodes, " "), ProgressNumber(Mean(cell.feasible_fractions)),
        fmt::join(cell.original_heavy_episodes, " "), WithinWidenedRange(cell),
        first_epoch_columns(cell.first_epochs), first_epoch_columns(cell.original_first_epochs),
        fmt::join(cell.hazard_steps, " "), fmt::join(cell.vase_steps, " "), cell.source);
  }
  return text;
}

double PairedSignFlipP(const std::vector<double>& differences) {
  const size_t n = differences.size();
  if (n == 0) return 1.0;
  double observed = 0.0;
  for (const double d : differences) observed += d;
  observed = std::abs(observed);
  // A sum within rounding of the observed one counts as "as far": sums of the same values in
  // another order may differ in their last bits.
  const double tolerance = 1e-9 * (1.0 + observed);
  // Whether the assignment whose bit i flips difference i (words of 64 bits) reaches it.
  std::vector<std::uint64_t> signs((n + 63) / 64);
  const auto as_far = [&] {
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
      sum += (signs[i / 64] >> (i % 64) & 1) ? -differences[i] : differences[i];
    }
    return std::abs(sum) >= observed - tolerance;
  };
  constexpr size_t kExactUpTo = 20;
  std::uint64_t hits = 0, total = 0;
  if (n <= kExactUpTo) {
    total = std::uint64_t{1} << n;
    for (signs[0] = 0; signs[0] < total; ++signs[0]) hits += as_far();
  } else {
    // A fixed seed: the p-value is a property of the values, and a report regenerates alike.
    std::mt19937_64 generator(0x5eedf11b);
    total = std::uint64_t{1} << kExactUpTo;
    for (std::uint64_t draw = 0; draw < total; ++draw) {
      for (std::uint64_t& word : signs) word = generator();
      hits += as_far();
    }
  }
  return static_cast<double>(hits) / static_cast<double>(total);
}

std::string SettingComparisonMarkdown(const std::vector<TableCell>& cells) {
  if (std::all_of(cells.begin(), cells.end(),
                  [](const TableCell& c) { return c.setting.empty(); })) {
    return "";
  }
  std::string text =
      "Each setting against the first of its task and method, paired by seed (the seeds both "
      "have): the per-seed differences (this setting's minus the first's) of violations and of "
      "the last-10-episode return, their mean [bootstrap 90% interval], and the two-sided "
      "p-value of an exact paired sign-flip test (with n pairs it cannot fall below 2/2^n).\n\n"
      "| task | method | setting | against | seeds | violations: differences | mean [90%] | p | "
      "return: differences | mean [90%] | p |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const TableCell& first : cells) {
    // The first cell of its task and method in the table's order is the one compared against.
    const auto same_pair = [&](const TableCell& c) {
      return c.task == first.task && c.planner == first.planner;
    };
    if (&*std::find_if(cells.begin(), cells.end(), same_pair) != &first) continue;
    for (const TableCell& other : cells) {
      if (&other == &first || !same_pair(other)) continue;
      std::vector<std::uint64_t> seeds;
      std::vector<double> violations, returns;
      for (size_t i = 0; i < other.seeds.size(); ++i) {
        const auto it = std::find(first.seeds.begin(), first.seeds.end(), other.seeds[i]);
        if (it == first.seeds.end()) continue;
        const size_t j = static_cast<size_t>(it - first.seeds.begin());
        seeds.push_back(other.seeds[i]);
        violations.push_back(other.per_seed[i] - first.per_seed[j]);
        if (std::isfinite(other.final_returns[i]) && std::isfinite(first.final_returns[j])) {
          returns.push_back(other.final_returns[i] - first.final_returns[j]);
        }
      }
      const auto p_value = [](const std::vector<double>& d) {
        return d.empty() ? std::string("-") : fmt::format("{:.3f}", PairedSignFlipP(d));
      };
      text += fmt::format(
          "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", first.task,
          MethodLabel(first.planner), other.setting.empty() ? "-" : other.setting,
          first.setting.empty() ? "-" : first.setting,
          seeds.empty() ? std::string("none") : fmt::format("{}", fmt::join(seeds, ", ")),
          PerSeed(violations, 1), MeanWithInterval(violations, 1), p_value(violations),
          PerSeed(returns, 2), MeanWithInterval(returns, 2), p_value(returns));
    }
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

std::vector<LearningCurve> LearningCurves(const std::vector<RunRecord>& runs,
                                          const std::string& task, CurveMetric metric,
                                          std::int64_t grid_step, std::int64_t smoothing,
                                          std::int64_t up_to) {
  Require(grid_step >= 1 && smoothing >= 1, "curve grid {} and smoothing {} must be positive",
          grid_step, smoothing);
  std::vector<LearningCurve> curves;
  const auto planner_of = [](const RunRecord& r) { return MethodOf(r.config); };
  const std::vector<std::string> settings = SettingsInOrder(runs);
  for (const std::string& planner : InOrder(runs, planner_of, MethodNames())) {
    for (const std::string& setting : settings) {
      std::vector<const RunRecord*> members;
      std::int64_t longest = 0;
      for (const RunRecord& run : runs) {
        if (run.config.task != task || MethodOf(run.config) != planner ||
            SettingOf(run) != setting || run.episodes.empty()) {
          continue;
        }
        members.push_back(&run);
        longest = std::max(longest, std::min(StepsReached(run), up_to));
      }
      if (members.empty()) continue;
      LearningCurve curve;
      curve.planner = planner;
      curve.setting = setting;
      for (std::int64_t x = grid_step; x <= longest; x += grid_step) {
        std::vector<double> values;
        for (const RunRecord* run : members) {
          if (StepsReached(*run) < x) continue;  // this seed has not reached x
          std::vector<double> window;
          for (const EpisodePoint& e : run->episodes) {
            if (e.end_step > x - smoothing && e.end_step <= x) {
              window.push_back(metric == CurveMetric::kReturn ? e.episode_return : e.episode_cost);
            }
          }
          if (!window.empty()) values.push_back(Mean(window));
        }
        if (values.empty()) continue;
        curve.steps.push_back(static_cast<double>(x));
        curve.mean.push_back(Mean(values));
        curve.std.push_back(SampleStd(values));
      }
      curves.push_back(curve);
    }
  }
  return curves;
}

namespace {

// The paper's preset of a run's task and method: configs_dir/<task>-<method>.yaml when there is
// one, else the defaults (the paper's values) with the run's task and method.
TrainConfig PaperPreset(const TrainConfig& run, const std::string& configs_dir) {
  std::string stem = run.task + "-" + MethodOf(run);
  std::transform(stem.begin(), stem.end(), stem.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  const fs::path preset = fs::path(configs_dir) / (stem + ".yaml");
  if (!configs_dir.empty() && fs::is_regular_file(preset)) return LoadTrainConfig(preset.string());
  TrainConfig paper;
  paper.task = run.task;
  paper.variant = run.variant;
  paper.algorithm = run.algorithm;
  paper.planner = run.planner;
  return paper;
}

}  // namespace

std::vector<std::string> SetupDifferences(const std::vector<RunRecord>& runs, std::int64_t window,
                                          const std::string& configs_dir) {
  std::vector<std::string> notes;
  std::set<std::string> seen;
  const auto note = [&](const std::string& text) {
    if (seen.insert(text).second) notes.push_back(text);
  };
  // Every key of every run against the paper's preset of its task and method, generic over the
  // config's keys (ConfigDifferences): (key, ours, the paper's) -> the cells that differ so.
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<std::string>> differing;
  std::vector<std::tuple<std::string, std::string, std::string>> order;
  std::map<std::string, std::set<std::uint64_t>> seeds;
  for (const RunRecord& run : runs) {
    const TrainConfig& c = run.config;
    // Seeds as Table I counts them: a run without a finished episode is not in it.
    if (!run.episodes.empty())
      seeds[c.task + " " + MethodOf(c) + " " + SettingOf(run)].insert(c.seed);
    const TrainConfig paper = PaperPreset(c, configs_dir);
    const std::string cell = fmt::format("{} {}", c.task, MethodLabel(MethodOf(c)));
    for (const ConfigDifference& d : ConfigDifferences(c, paper)) {
      const auto key = std::make_tuple(d.key, d.ours, d.theirs);
      auto& cells = differing[key];
      if (cells.empty()) order.push_back(key);
      if (std::find(cells.begin(), cells.end(), cell) == cells.end()) cells.push_back(cell);
    }
  }
  for (const auto& key : order) {
    const auto& [name, ours, theirs] = key;
    note(fmt::format("`{}` is {}, the paper's {} ({}).", name, ours, theirs,
                     fmt::join(differing[key], ", ")));
  }
  note(fmt::format("Table I here counts the first {} agent steps; the paper's, 10,000.", window));
  size_t fewest = SIZE_MAX, most = 0;
  for (const auto& entry : seeds) {
    fewest = std::min(fewest, entry.second.size());
    most = std::max(most, entry.second.size());
  }
  if (fewest == most && fewest != 3) {
    note(fmt::format("Seeds: {} per cell, the paper 3.", fewest));
  } else if (fewest < most) {
    note(fmt::format("Seeds: {} to {} per cell (Table I gives each cell's), the paper 3.", fewest,
                     most));
  }
  note(
      "Simulator: MuJoCo 2.2.2 through our own C++ re-creation of the tasks; the paper ran "
      "mujoco_py 2.0.2.7 with MuJoCo 2.0, so contacts and solver details differ and no "
      "trajectory is the paper's.");
  note(
      "Random numbers: our generators are not NumPy's or PyTorch's, so seed 0 here is not the "
      "paper's seed 0.");
  return notes;
}

namespace {

// One cell against the original: its seeds over the same window when its logs cover it, else
// Table I when the window is the paper's; nothing otherwise.
std::optional<std::string> OriginalComparison(const TableCell& cell, std::int64_t window) {
  const std::string label = fmt::format("{} {}", RowLabel(cell), MethodLabel(cell.planner));
  if (!cell.original_per_seed.empty()) {
    const std::string verdict = VersusOriginal(cell);
    return fmt::format(
        "{}: {:.1f} in the first {} steps, the original {:.1f} ({}); ours is {} its seeds' "
        "range{}.",
        label, cell.mean, window, Mean(cell.original_per_seed), Counts(cell.original_per_seed),
        verdict,
        verdict == "inside"  ? ""
        : verdict == "above" ? ": more violations than the original"
                             : ": fewer violations than the original");
  }
  if (cell.paper && window == kPaperWindow) {
    return fmt::format("{}: {:.1f} against the paper's {:.0f} ({:.2f}x).", label, cell.mean,
                       *cell.paper, *cell.paper > 0 ? cell.mean / *cell.paper : 0.0);
  }
  return std::nullopt;
}

// Per task: whether the paper's method (MPC-RCE) violated less than each other planner, and
// whether its final return is comparable to the best other's.
void PapersMethodAgainstOthers(const std::string& task,
                               const std::map<std::string, const TableCell*>& row,
                               const TableCell& method, std::vector<std::string>& notes) {
  const std::string name = MethodLabel(method.planner);
  std::vector<std::string> worse, not_worse;
  for (const auto& [planner, cell] : row) {
    if (cell == &method) continue;
    (cell->mean > method.mean ? worse : not_worse).push_back(MethodLabel(planner));
  }
  if (!worse.empty() || !not_worse.empty()) {
    notes.push_back(fmt::format(
        "{}: {} {:.1f} violations on average; {}{}{}.", task, name, method.mean,
        worse.empty() ? "" : fmt::format("more for {}", fmt::join(worse, " and ")),
        !worse.empty() && !not_worse.empty() ? "; " : "",
        not_worse.empty() ? ""
                          : fmt::format("NOT more for {} (the paper's claim fails here)",
                                        fmt::join(not_worse, " and "))));
  }
  double best_other = -std::numeric_limits<double>::infinity();
  std::string best_label;
  for (const auto& [planner, cell] : row) {
    if (cell != &method && cell->return_mean > best_other) {
      best_other = cell->return_mean;
      best_label = MethodLabel(planner);
    }
  }
  if (!best_label.empty()) {
    notes.push_back(
        fmt::format("{}: {}'s final return {:.2f} against {:.2f} for {}, the best of the others{}.",
                    task, name, method.return_mean, best_other, best_label,
                    method.return_mean >= 0.8 * best_other || best_other <= 0
                        ? ""
                        : " (less than 80% of it: not comparable reward)"));
  }
}

}  // namespace

std::vector<std::string> WhereRunsWereMade(const std::vector<RunRecord>& runs) {
  std::vector<std::pair<NumericsSetup, std::vector<std::string>>> setups;  // in order of first use
  std::vector<std::string> unrecorded, moved;
  for (const RunRecord& run : runs) {
    if (run.sessions.empty()) unrecorded.push_back(run.name);
    for (size_t i = 0; i < run.sessions.size(); ++i) {
      const RunSession& session = run.sessions[i];
      auto setup = std::find_if(setups.begin(), setups.end(),
                                [&](const auto& known) { return known.first == session.setup; });
      if (setup == setups.end()) setup = setups.insert(setups.end(), {session.setup, {}});
      std::vector<std::string>& names = setup->second;
      if (std::find(names.begin(), names.end(), run.name) == names.end()) {
        names.push_back(run.name);
      }
      if (i == 0) continue;
      const std::vector<std::string> changes =
          SetupChanges(run.sessions[i - 1].setup, session.setup);
      if (!changes.empty()) {
        moved.push_back(fmt::format("{} at step {} ({})", run.name, session.steps_done,
                                    fmt::join(changes, ", ")));
      }
    }
  }
  const auto count = [](size_t n) { return fmt::format("{} run{}", n, n == 1 ? "" : "s"); };
  std::vector<std::string> notes;
  for (const auto& [setup, names] : setups) {
    notes.push_back(fmt::format("{}: {} ({}).", DescribeSetup(setup), count(names.size()),
                                fmt::join(names, ", ")));
  }
  if (!moved.empty()) {
    notes.push_back(fmt::format(
        "Resumed on another setup than their previous session's, so that their rows after that "
        "step are not those of an uninterrupted run: {}.",
        fmt::join(moved, "; ")));
  }
  if (!unrecorded.empty()) {
    notes.push_back(fmt::format("Not recorded (begun before runs kept sessions.jsonl): {} ({}).",
                                count(unrecorded.size()), fmt::join(unrecorded, ", ")));
  }
  return notes;
}

std::vector<std::string> OutcomeDifferences(const std::vector<TableCell>& cells,
                                            std::int64_t window) {
  std::vector<std::string> notes;
  // One row per task and setting: the paper's method is compared within its own setting.
  std::map<std::string, std::map<std::string, const TableCell*>> by_row;
  std::vector<std::string> rows;
  for (const TableCell& cell : cells) {
    const std::string row = RowLabel(cell);
    if (by_row.find(row) == by_row.end()) rows.push_back(row);
    by_row[row][cell.planner] = &cell;
  }
  for (const std::string& label : rows) {
    const auto& row = by_row[label];
    for (const auto& [planner, cell] : row) {
      if (IsPapersMethod(planner)) PapersMethodAgainstOthers(label, row, *cell, notes);
    }
    for (const TableCell& cell : cells) {  // the table's planner order
      if (RowLabel(cell) != label) continue;
      if (const auto note = OriginalComparison(cell, window)) notes.push_back(*note);
    }
  }
  return notes;
}

}  // namespace cmbrl

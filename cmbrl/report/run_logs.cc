#include "cmbrl/report/run_logs.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <thread>
#include <tuple>

#include "cmbrl/core/check.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/run/progress_columns.h"
#include "cmbrl/run/progress_table.h"
#include "cmbrl/run/run_directory.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

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

// A row's value of a column that must lie in [low, high] (finite), named in the error.
double InDomain(const ProgressTable& table, const std::string& file, size_t row, size_t column,
                double low, double high, const char* expected) {
  const double value = table.Number(row, column);
  Require(std::isfinite(value) && value >= low && value <= high,
          "{} line {}: {} is {}: expected {}", file, table.line(row), table.header().at(column),
          table.Text(row, column), expected);
  return value;
}

// The clock columns of a progress log (either family), where it has them: Time and CpuTime.
struct ClockColumns {
  std::optional<size_t> time, cpu_time;
};

ClockColumns FindClockColumns(const ProgressTable& table, const std::string& expected) {
  ClockColumns clocks;
  if (table.HasColumn(kTimeColumn)) clocks.time = table.Column(kTimeColumn, expected);
  if (table.HasColumn(kCpuTimeColumn)) clocks.cpu_time = table.Column(kCpuTimeColumn, expected);
  return clocks;
}

// A row's wall and CPU seconds so far, each finite and not negative, into `point` (left NaN where
// the log has no such column).
void ReadClocks(const ProgressTable& table, const std::string& file, size_t row,
                const ClockColumns& clocks, EpisodePoint& point) {
  constexpr double kNoLimit = std::numeric_limits<double>::infinity();
  if (clocks.time) {
    point.elapsed_seconds = InDomain(table, file, row, *clocks.time, 0.0, kNoLimit,
                                     "the run's wall seconds so far (0 or more)");
  }
  if (clocks.cpu_time) {
    point.cpu_seconds = InDomain(table, file, row, *clocks.cpu_time, 0.0, kNoLimit,
                                 "the run's CPU seconds so far (0 or more)");
  }
}

// The same for a count of steps in an episode of `steps` steps: a whole number in [0, steps].
double StepCount(const ProgressTable& table, const std::string& file, size_t row, size_t column,
                 double steps) {
  const double value =
      InDomain(table, file, row, column, 0.0, steps, "a whole count from 0 to the episode's steps");
  Require(value == std::round(value), "{} line {}: {} is {}: expected a whole count", file,
          table.line(row), table.header().at(column), table.Text(row, column));
  return value;
}

// The same for a column where NaN means "not measured" (a fraction not logged, the means of an
// epoch in which no episode ended): NaN passes, any other value must lie in [low, high].
double NanOrInDomain(const ProgressTable& table, const std::string& file, size_t row, size_t column,
                     double low, double high, const char* expected) {
  const double value = table.Number(row, column);
  return std::isnan(value) ? value : InDomain(table, file, row, column, low, high, expected);
}

std::optional<size_t> RowLimit(std::optional<std::int64_t> rows) {
  if (!rows) return std::nullopt;
  return static_cast<size_t>(std::max<std::int64_t>(*rows, 0));
}

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The folders under `parent` that hold a run (config.yaml), in name order. Throws cmbrl::Error
// naming a folder with a run's log but no config.yaml (deleted by hand): such a run can be
// neither read nor silently left out of a count.
std::vector<fs::path> RunFolders(const fs::path& parent) {
  std::vector<fs::path> dirs;
  if (!fs::is_directory(parent)) return dirs;
  for (const fs::directory_entry& entry : fs::directory_iterator(parent)) {
    if (!entry.is_directory()) continue;
    const RunDirectory run(entry.path());
    if (run.HoldsRun()) {
      dirs.push_back(entry.path());
    } else {
      Require(!fs::exists(run.progress_file()),
              "'{}' has a progress.csv but no config.yaml: the run cannot be read without it "
              "(restore its config.yaml, or move the folder away)",
              entry.path().string());
    }
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
  const ProgressLog log = FamilyOf(run.config.algorithm).log;
  run.epoch_log = log == ProgressLog::kEpochs;
  run.episodes = EpisodeReaderOf(log)(run_dir.progress_file().string(), rows);
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

std::string SettingOf(const RunRecord& run) {
  const std::string named =
      SettingOfRunName(run.name, run.config.task, MethodOf(run.config), run.config.seed);
  if (run.config_setting.empty()) return named;
  return named.empty() ? run.config_setting : named + "-" + run.config_setting;
}

std::vector<std::string> SettingsInOrder(const std::vector<RunRecord>& runs,
                                         const std::vector<std::string>& declared) {
  std::vector<std::string> natural;
  for (const RunRecord& run : runs) natural.push_back(SettingOf(run));
  std::sort(natural.begin(), natural.end(), NaturalLess);
  natural.erase(std::unique(natural.begin(), natural.end()), natural.end());
  const auto held = [](const std::vector<std::string>& list, const std::string& setting) {
    return std::find(list.begin(), list.end(), setting) != list.end();
  };
  std::vector<std::string> settings;
  for (const std::string& setting : declared) {
    if (held(natural, setting) && !held(settings, setting)) settings.push_back(setting);
  }
  for (const std::string& setting : natural) {
    if (!held(settings, setting)) settings.push_back(setting);
  }
  return settings;
}

std::vector<std::string> TasksInOrder(const std::vector<RunRecord>& runs) {
  return InOrder(
      runs, [](const RunRecord& r) { return r.config.task; }, EnvNames());
}

std::vector<std::string> MethodsInOrder(const std::vector<RunRecord>& runs) {
  return InOrder(
      runs, [](const RunRecord& r) { return MethodOf(r.config); }, MethodNames());
}

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
  const bool has_causes = table.HasColumn(kHazardStepsColumn) && table.HasColumn(kVaseStepsColumn);
  const size_t hazards = has_causes ? table.Column(kHazardStepsColumn, expected) : 0;
  const size_t vases = has_causes ? table.Column(kVaseStepsColumn, expected) : 0;
  const ClockColumns clocks = FindClockColumns(table, expected);
  std::vector<EpisodePoint> episodes;
  for (size_t row = 0; row < table.rows(); ++row) {
    EpisodePoint point;
    const std::int64_t previous = episodes.empty() ? 0 : episodes.back().end_step;
    point.end_step =
        static_cast<std::int64_t>(InDomain(table, file, row, total, static_cast<double>(previous),
                                           kInfinity, "a count of steps that never falls"));
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
    ReadClocks(table, file, row, clocks, point);
    point.cumulative_violations =
        (episodes.empty() ? 0.0 : episodes.back().cumulative_violations) + point.episode_cost;
    episodes.push_back(point);
  }
  return episodes;
}

fs::path RunLogsDir(const fs::path& report_dir) { return report_dir / kLogsFolder; }

namespace {

// A task's runs are pooled: one name must mean one environment. A task of one's own says what
// makes it (python.env, or its mujoco_task section); a built-in one is its name. Throws
// cmbrl::Error naming two runs of one task name made on different environments.
void RequireOneEnvironmentPerTask(
    const std::map<std::string, std::pair<RunRecord, bool>>& found) {
  std::map<std::string, std::pair<std::string, fs::path>> environments;  // task -> (what, where)
  for (const auto& [name, entry] : found) {
    const TrainConfig& c = entry.first.config;
    const std::string made =
        !c.python.env.empty()          ? "python.env " + c.python.env
        : IsDeclaredTask(c.mujoco_task) ? "their mujoco_task sections differ"
                                       : "";
    TrainConfig environment;  // its task section and its environment's name, all else default
    environment.mujoco_task = c.mujoco_task;
    environment.python.env = c.python.env;
    const std::string what = made.empty() ? "" : TrainConfigToYaml(environment);
    const auto [it, first] = environments.emplace(c.task, std::make_pair(what, entry.first.source));
    Require(first || it->second.first == what,
            "'{}' and '{}' both name task '{}' but were made on different environments ({}): a "
            "report pools the runs of one task; give them names of their own",
            it->second.second.string(), entry.first.source.string(), c.task,
            made.empty() ? "a built-in task and one of its own" : made);  // the later one's
  }
}

// The runs of each cell its runs' names make (task, method, setting; SettingOf) in name order.
std::map<std::tuple<std::string, std::string, std::string>, std::vector<RunRecord*>> CellsOf(
    std::vector<RunRecord>& runs) {
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<RunRecord*>> cells;
  for (RunRecord& run : runs) {
    cells[{run.config.task, MethodOf(run.config), SettingOf(run)}].push_back(&run);
  }
  return cells;
}

// How two runs' configs differ as a report's cells see it: every key of ConfigDifferences but the
// budget (training.total_steps), since a report counts a window of the runs' steps.
std::vector<ConfigDifference> CellDifferences(const TrainConfig& a, const TrainConfig& b) {
  std::vector<ConfigDifference> differences = ConfigDifferences(a, b);
  differences.erase(
      std::remove_if(differences.begin(), differences.end(),
                     [](const ConfigDifference& d) { return d.key == "training.total_steps"; }),
      differences.end());
  return differences;
}

// Whether a cell's label already gives the key of `word` ("population=500" in
// "population=500-gamma=0.99").
bool LabelNames(const std::string& label, const std::string& word) {
  const std::string axis = word.substr(0, word.find('=') + 1);
  return ("-" + label).find("-" + axis) != std::string::npos;
}

// The keys some of `configs` differ in (CellDifferences against the first, in the order first
// met), and each config's setting word for each of them: words[config][key].
struct DifferingKeys {
  std::vector<std::string> keys;
  std::vector<std::vector<std::string>> words;
};

DifferingKeys DifferingKeysOf(const std::vector<const TrainConfig*>& configs) {
  DifferingKeys found;
  std::map<std::string, std::string> firsts;  // key -> the first config's value
  std::vector<std::map<std::string, std::string>> own(configs.size());  // key -> a config's value
  for (size_t i = 1; i < configs.size(); ++i) {
    for (const ConfigDifference& d : CellDifferences(*configs[i], *configs.front())) {
      if (firsts.emplace(d.key, d.theirs).second) found.keys.push_back(d.key);
      own[i][d.key] = d.ours;
    }
  }
  for (size_t i = 0; i < configs.size(); ++i) {
    std::vector<std::string>& words = found.words.emplace_back();
    for (const std::string& key : found.keys) {
      const auto it = own[i].find(key);
      words.push_back(SettingWord(key, it != own[i].end() ? it->second : firsts[key]));
    }
  }
  return found;
}

// Sets config_setting where the runs that one cell would hold differ in their configs: each of
// them gets its values of every key some of them differ in (ConfigDifferences: not the seed,
// the device, the thread counts or the budget), in the order they are first met; a key its name's
// setting already gives (an axis) is not repeated.
void TellConfigsApart(std::vector<RunRecord>& runs) {
  for (auto& [cell, members] : CellsOf(runs)) {
    std::vector<const TrainConfig*> configs;
    for (const RunRecord* run : members) configs.push_back(&run->config);
    const DifferingKeys differing = DifferingKeysOf(configs);
    if (differing.keys.empty()) continue;
    const std::string& named = std::get<2>(cell);
    for (size_t i = 0; i < members.size(); ++i) {
      std::vector<std::string> words;
      for (const std::string& word : differing.words[i]) {
        if (!LabelNames(named, word)) words.push_back(word);
      }
      members[i]->config_setting = fmt::format("{}", fmt::join(words, "-"));
    }
  }
}

// Whether a cell's label holds a word given by hand ("policy" in "policy-gamma=0.9"): a word
// that is no key's value, which the runs' names gave to tell their cell apart.
bool LabelHasOwnWord(const std::string& label) {
  for (size_t begin = 0; begin < label.size();) {
    const size_t end = std::min(label.find('-', begin), label.size());
    const std::string part = label.substr(begin, end - begin);
    // A part after a '-' inside a value ("gamma=-0.5") is a number.
    if (!part.empty() && std::isalpha(static_cast<unsigned char>(part.front())) &&
        part.find('=') == std::string::npos) {
      return true;
    }
    begin = end + 1;
  }
  return false;
}

// Adds to the labels of the cells of one task and method what their configs differ in and
// neither label says: a report of two experiments, one's cells named by an axis and the other's
// by nothing, would otherwise show a cell of another config under the plain task's name, read as
// the preset's. A key one of two cells names (an axis beside the preset) is left as it is: the
// plain cell is the other value; so is a difference beside a word given by hand, which names it.
void TellCellsApart(std::vector<RunRecord>& runs) {
  std::map<std::pair<std::string, std::string>, std::vector<std::vector<RunRecord*>>> rows;
  for (auto& [cell, members] : CellsOf(runs)) {
    rows[{std::get<0>(cell), std::get<1>(cell)}].push_back(members);
  }
  for (auto& [row, cells] : rows) {
    std::vector<const TrainConfig*> configs;  // each cell's, as its first run has it
    std::vector<std::string> labels;
    std::vector<bool> silent;  // no word given by hand in the cell's label
    for (const std::vector<RunRecord*>& members : cells) {
      configs.push_back(&members.front()->config);
      labels.push_back(SettingOf(*members.front()));
      silent.push_back(!LabelHasOwnWord(labels.back()));
    }
    const DifferingKeys differing = DifferingKeysOf(configs);
    std::vector<std::vector<std::string>> added(cells.size());
    for (size_t k = 0; k < differing.keys.size(); ++k) {
      // Whether cell i leaves its value of the key unsaid.
      const auto unsaid_by = [&](size_t i) {
        return silent[i] && !LabelNames(labels[i], differing.words[i][k]);
      };
      std::vector<bool> unsaid(cells.size(), false);
      for (size_t i = 0; i < cells.size(); ++i) {
        for (size_t j = i + 1; j < cells.size(); ++j) {
          if (differing.words[i][k] != differing.words[j][k] && unsaid_by(i) && unsaid_by(j)) {
            unsaid[i] = unsaid[j] = true;
          }
        }
      }
      for (size_t i = 0; i < cells.size(); ++i) {
        if (unsaid[i]) added[i].push_back(differing.words[i][k]);
      }
    }
    for (size_t i = 0; i < cells.size(); ++i) {
      if (added[i].empty()) continue;
      const std::string more = fmt::format("{}", fmt::join(added[i], "-"));
      for (RunRecord* run : cells[i]) {
        run->config_setting = run->config_setting.empty() ? more : run->config_setting + "-" + more;
      }
    }
  }
}

// A cell pools the seeds of one config: throws cmbrl::Error naming two runs of a cell made with
// different configs (runs whose names give one setting, told apart by keys that still match
// another's). Two runs of one seed are the table's to refuse (ViolationTable): a run that a
// report leaves out, short of its window, may share a seed with one it counts.
void RequireOneConfigPerCell(std::vector<RunRecord>& runs) {
  for (auto& [cell, members] : CellsOf(runs)) {
    const RunRecord& first = *members.front();
    for (size_t i = 1; i < members.size(); ++i) {
      const RunRecord& run = *members[i];
      const std::vector<ConfigDifference> differences = CellDifferences(run.config, first.config);
      Require(differences.empty(),
              "'{}' and '{}' fall in one cell ({} {}{}) but were made with different configs "
              "('{}' is {} in the first, {} in the second): a cell pools the seeds of one "
              "config; report them apart",
              first.source.string(), run.source.string(), std::get<0>(cell), std::get<1>(cell),
              std::get<2>(cell).empty() ? "" : " " + std::get<2>(cell),
              differences.empty() ? "" : differences.front().key,
              differences.empty() ? "" : differences.front().theirs,
              differences.empty() ? "" : differences.front().ours);
    }
  }
}

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
  RequireOneEnvironmentPerTask(found);
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
  TellConfigsApart(runs);
  TellCellsApart(runs);
  RequireOneConfigPerCell(runs);
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

double SecondsTaken(const RunRecord& run) {
  return run.episodes.empty() ? std::numeric_limits<double>::quiet_NaN()
                              : run.episodes.back().elapsed_seconds;
}

double CpuSecondsTaken(const RunRecord& run) {
  return run.episodes.empty() ? std::numeric_limits<double>::quiet_NaN()
                              : run.episodes.back().cpu_seconds;
}

int SessionCores(const NumericsSetup& setup) {
  return std::max({1, setup.blas_threads, setup.torch_threads});
}

double CoreSecondsTaken(const RunRecord& run) {
  const double seconds = SecondsTaken(run);
  if (!std::isfinite(seconds) || run.sessions.empty()) return seconds;
  // The time the run's points had reached at a step (0 before its first point).
  const auto reached_at = [&](std::int64_t step) {
    double reached = 0.0;
    for (const EpisodePoint& point : run.episodes) {
      if (point.end_step > step) break;
      if (std::isfinite(point.elapsed_seconds)) reached = point.elapsed_seconds;
    }
    return reached;
  };
  double core_seconds = 0.0;
  for (size_t k = 0; k < run.sessions.size(); ++k) {
    const double from = reached_at(run.sessions[k].steps_done);
    const double to =
        k + 1 < run.sessions.size() ? reached_at(run.sessions[k + 1].steps_done) : seconds;
    core_seconds += std::max(0.0, to - from) * SessionCores(run.sessions[k].setup);
  }
  return core_seconds;
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

EpisodeReader EpisodeReaderOf(ProgressLog log) {
  switch (log) {
    case ProgressLog::kEpisodes:
      return ReadProgressEpisodes;
    case ProgressLog::kEpochs:
      return ReadEpochLog;
  }
  Fail("no reader for this kind of progress log");
}

std::vector<EpisodePoint> ReadEpochLog(const std::string& file, std::optional<std::int64_t> rows) {
  const ProgressTable table = ProgressTable::Read(file, RowLimit(rows));
  const std::string expected =
      fmt::format("a model-free progress log with {}, {}, {} and {}", kAverageEpRetColumn,
                  kAverageEpCostColumn, kCumulativeCostColumn, kTotalEnvInteractsColumn);
  const size_t ret = table.Column(kAverageEpRetColumn, expected);
  const size_t cost = table.Column(kAverageEpCostColumn, expected);
  const size_t cumulative = table.Column(kCumulativeCostColumn, expected);
  const size_t total = table.Column(kTotalEnvInteractsColumn, expected);
  const ClockColumns clocks = FindClockColumns(table, expected);
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
    point.episode_cost =
        NanOrInDomain(table, file, row, cost, 0.0, kInfinity,
                      "a finite mean cost of 0 or more (or nan: no episode ended)");
    point.cumulative_violations =
        InDomain(table, file, row, cumulative, before, before + point.steps,
                 "a running count that rises by at most the epoch's steps");
    ReadClocks(table, file, row, clocks, point);
    epochs.push_back(point);
  }
  return epochs;
}

}  // namespace cmbrl

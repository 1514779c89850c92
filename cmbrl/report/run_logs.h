// Runs as a report reads them: each run's config and its progress log as episode (or epoch)
// points, read from a sweep's runs/ or a report's run-logs/, and the logs a report keeps.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/run/run_sessions.h"

namespace cmbrl {

// One episode of a run's progress.csv.
struct EpisodePoint {
  std::int64_t end_step = 0;  // TotalEnvInteracts after the episode
  int steps = 0;              // agent steps of the episode
  double episode_return = 0.0;
  double episode_cost = 0.0;
  double feasible_fraction = std::numeric_limits<double>::quiet_NaN();  // NaN: not logged
  // Its violating steps in hazards and at vases (HazardSteps, VaseSteps; NaN: not logged).
  double hazard_steps = std::numeric_limits<double>::quiet_NaN();
  double vase_steps = std::numeric_limits<double>::quiet_NaN();
  // The run's violations from its start through this point (the running sum of EpCost for an
  // MPC run, CumulativeCost for a model-free one).
  double cumulative_violations = 0.0;
  // The run's wall seconds at this point, over all its sessions (Time; the work an interruption
  // threw away not counted); NaN: not logged.
  double elapsed_seconds = std::numeric_limits<double>::quiet_NaN();
  // The CPU seconds its process had used at this point, over all its sessions (CpuTime); NaN:
  // not logged (a run begun before CpuTime was kept).
  double cpu_seconds = std::numeric_limits<double>::quiet_NaN();
};

struct RunRecord {
  std::string name;  // the run directory's name
  TrainConfig config;
  // One point per MPC episode, or per epoch of a model-free run (episode_return and
  // episode_cost then the epoch's AverageEpRet and AverageEpCost, steps its environment steps).
  std::vector<EpisodePoint> episodes;
  bool epoch_log = false;  // the points are epochs (model-free)
  // The folder its config.yaml and progress.csv were read from: a sweep's runs/<name>, or a
  // report's run-logs/<name> (KeepRunLogs).
  std::filesystem::path source;
  // Where each of its sessions ran (empty: a run begun before runs kept sessions.jsonl).
  std::vector<RunSession> sessions;
  // What sets its config apart from the other runs its name puts in one cell, and from the
  // cells of its task and method whose labels would not say how they differ (ReadSweeps): the
  // keys they differ in, as words of a setting ("population=500", several joined by '-'); ""
  // where they agree, as a sweep's runs of one setting do.
  std::string config_setting;
};

// Which learner families some runs or table cells hold (anything with an `epoch_log` flag):
// MPC runs count agent steps and episodes, model-free ones environment steps and epochs.
struct FamiliesPresent {
  bool mpc = false;
  bool model_free = false;
};
template <typename Item>
FamiliesPresent FamiliesIn(const std::vector<Item>& items) {
  FamiliesPresent present;
  for (const Item& item : items) (item.epoch_log ? present.model_free : present.mpc) = true;
  return present;
}

// The epochs of a model-free run's progress.csv as points (see RunRecord), its first `rows`
// rows only when given (those its checkpoint covers). Throws cmbrl::Error naming the file, the
// line and the column of a missing column, a value that is not a number, or one outside its
// domain: a return that is not finite, a cost that is negative or not finite, a
// CumulativeCost that falls, steps that do not rise.
std::vector<EpisodePoint> ReadEpochLog(const std::string& path,
                                       std::optional<std::int64_t> rows = std::nullopt);

// The episodes of one progress.csv, its first `rows` rows only when given. Throws
// cmbrl::Error naming the file, the line and the column of a missing column, a value that is
// not a number, or one outside its domain: a return that is not finite, an EpCost,
// HazardSteps or VaseSteps that is not a whole count from 0 to the episode's steps, a
// FeasibleFraction outside 0 to 1, steps that fall.
std::vector<EpisodePoint> ReadProgressEpisodes(const std::string& path,
                                               std::optional<std::int64_t> rows = std::nullopt);

// The reader of each kind of progress.csv a family's sheet names (run/learner_family.h), the one
// place that pairs them: a row per episode (ReadProgressEpisodes), a row per epoch
// (ReadEpochLog).
using EpisodeReader = std::vector<EpisodePoint> (*)(const std::string& path,
                                                    std::optional<std::int64_t> rows);
EpisodeReader EpisodeReaderOf(ProgressLog log);

// The same from any CSV with the columns EpRet, EpCost and TotalEnvInteracts, and Steps when
// `has_steps` (without it an episode's steps are the difference of TotalEnvInteracts, as in the
// original's logs).
std::vector<EpisodePoint> ReadEpisodeColumns(const std::string& path, bool has_steps,
                                             std::optional<std::int64_t> rows = std::nullopt);

// Every run under sweep_dir/runs (a folder with config.yaml, its progress checked against its
// checkpoint) and every run log a report kept under sweep_dir/run-logs (KeepRunLogs), in name
// order: a report's folder can be reported again. A run in runs/ is read as far as its last
// checkpoint covers (rows after it are a run in progress, or were added by hand). A run both
// logged and in runs/ is read from runs/ when its log is a prefix of the run's progress (the
// run went on after the report). Throws cmbrl::Error naming a progress.csv that lacks a column
// or holds a value that is not a number or lies outside its domain, a folder that holds
// neither, a run found twice otherwise, or two folders that hold one run (the same run id in
// sessions.jsonl: a copied run folder).
std::vector<RunRecord> ReadSweep(const std::string& sweep_dir);

// ReadSweep over several folders, in name order. Runs that their names put in one cell (one
// task, method and setting) but that were made with different configs, such as runs named by
// hand, are told apart by the keys they differ in (config_setting), so that a cell pools the
// seeds of one config; so are two cells of one task and method whose configs differ in a key
// neither's label names (one experiment's preset cell beside another's axis cells). Throws
// cmbrl::Error naming a run found in two of the folders (except a log and the run it is a prefix
// of, as in ReadSweep), and two runs that a cell would still hold with different configs.
std::vector<RunRecord> ReadSweeps(const std::vector<std::string>& sweep_dirs);

// Writes each run's config.yaml, progress.csv and sessions.jsonl (where it has one), as they are
// now, to out/run-logs/<name>/, so
// that the report's folder holds what it was made from and can be made again without the runs
// (their checkpoints are not kept). run-logs/, not logs/: a sweep's logs/ holds its runs'
// output. Replaces a previous report's run-logs/ whole (written beside it, then swapped in),
// after reading every source. Throws cmbrl::Error when out/run-logs holds anything but such
// logs, or a file cannot be written.
void KeepRunLogs(const std::vector<RunRecord>& runs, const std::string& out);

// Where a report folder keeps its runs' logs: report_dir/run-logs.
std::filesystem::path RunLogsDir(const std::filesystem::path& report_dir);

// The agent (or environment) steps a run's progress has reached: its last point's end, 0 before
// its first.
std::int64_t StepsReached(const RunRecord& run);

// The wall seconds a run has taken so far: its last point's elapsed_seconds (NaN before its
// first point, or where its log has no Time).
double SecondsTaken(const RunRecord& run);

// The CPU seconds a run has used so far: its last point's cpu_seconds (NaN before its first
// point, or where its log has no CpuTime).
double CpuSecondsTaken(const RunRecord& run);

// The cores a session ran on, as its setup records them: the more of OpenBLAS's and LibTorch's
// threads (a sweep sets them to the cores it gives a run), at least 1 (a session of a version
// that recorded neither).
int SessionCores(const NumericsSetup& setup);

// The core-seconds a run has taken so far: each session's share of SecondsTaken (what its
// points' elapsed_seconds gained from the session's first step to the next session's) at that
// session's SessionCores; SecondsTaken itself for a run without sessions. NaN where SecondsTaken
// is.
double CoreSecondsTaken(const RunRecord& run);

// Removes the runs that have not reached `window` steps (StepsReached) from `runs`, and returns
// them as "name (N steps)", in order.
std::vector<std::string> LeaveOutRunsShortOf(std::vector<RunRecord>& runs, std::int64_t window);

// A run's setting: its values of an experiment's axes, read from its name (SweepRunName), then
// its config_setting; "" for a run of no axes whose config its cell's runs share.
std::string SettingOf(const RunRecord& run);

// Whether `a` sorts before `b` with the numbers in them compared by value ("gamma=0.9" before
// "gamma=0.98", "population=100" before "population=500"): an experiment's settings in order.
bool NaturalLess(const std::string& a, const std::string& b);

// The runs' distinct settings: those of `declared` in its order (an experiment's, as its axes
// list them), then the rest in natural order ("" first: runs of no axes).
std::vector<std::string> SettingsInOrder(const std::vector<RunRecord>& runs,
                                         const std::vector<std::string>& declared = {});

// The runs' distinct tasks and methods, in the registries' order (the paper's), unknown ones
// last.
std::vector<std::string> TasksInOrder(const std::vector<RunRecord>& runs);
std::vector<std::string> MethodsInOrder(const std::vector<RunRecord>& runs);

}  // namespace cmbrl

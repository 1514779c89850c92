// What a sweep found (paper Section V): Table I, violations during learning per task and
// planner with the paper's numbers beside ours, and the learning curves of EpRet and EpCost.
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
};

// An episode with at least this many violations is a "heavy" one: on level 2 a few such
// episodes (a robot held at a hazard's edge that slips in again and again) hold most of a run's
// violations.
inline constexpr double kHeavyEpisodeCost = 20.0;

// Episodes that ended within the window with at least kHeavyEpisodeCost violations.
int HeavyEpisodesWithin(const RunRecord& run, std::int64_t window);

// Mean FeasibleFraction of the episodes that ended within the window (NaN when not logged).
double FeasibleFractionWithin(const RunRecord& run, std::int64_t window);

// Where a run's violations happened: its violating steps in hazards and at vases (a step can
// be both).
struct ViolationCauses {
  int hazard_steps = 0;
  int vase_steps = 0;
};

// The sums over the episodes that ended within the window; nullopt when one of them did not log
// them (a run of an older version, the original's logs, a model-free run).
std::optional<ViolationCauses> ViolationCausesWithin(const RunRecord& run, std::int64_t window);

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

// Each learner family's reader of its progress.csv, the one place that pairs them: MPC runs log
// a row per episode (ReadProgressEpisodes), model-free runs a row per epoch (ReadEpochLog).
using EpisodeReader = std::vector<EpisodePoint> (*)(const std::string& path,
                                                    std::optional<std::int64_t> rows);
EpisodeReader EpisodeReaderOf(LearnerFamily family);

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

// ReadSweep over several folders, in name order. Throws cmbrl::Error naming a run found in two
// of them (except a log and the run it is a prefix of, as in ReadSweep).
std::vector<RunRecord> ReadSweeps(const std::vector<std::string>& sweep_dirs);

// Writes each run's config.yaml, progress.csv and sessions.jsonl (where it has one), as they are
// now, to out/run-logs/<name>/, so
// that the report's folder holds what it was made from and can be made again without the runs
// (their checkpoints are not kept). run-logs/, not logs/: a sweep's logs/ holds its runs'
// output. Replaces a previous report's run-logs/ whole (written beside it, then swapped in),
// after reading every source. Throws cmbrl::Error when out/run-logs holds anything but such
// logs, or a file cannot be written.
void KeepRunLogs(const std::vector<RunRecord>& runs, const std::string& out);

// The agent (or environment) steps a run's progress has reached: its last point's end, 0 before
// its first.
std::int64_t StepsReached(const RunRecord& run);

// Removes the runs that have not reached `window` steps (StepsReached) from `runs`, and returns
// them as "name (N steps)", in order.
std::vector<std::string> LeaveOutRunsShortOf(std::vector<RunRecord>& runs, std::int64_t window);

// Violations during the first `window` agent steps of a run: the EpCost of every episode that
// ended within the window (TotalEnvInteracts <= window), the rule by which the original's logs
// give Table I and its counts over 3000 steps. For an epoch log (model-free, 30,000 steps an
// epoch) the cumulative cost is interpolated linearly within the epoch the window ends in.
double ViolationsWithin(const RunRecord& run, std::int64_t window);

// A run's first epoch: its first `training.episodes_per_epoch` MPC episodes (the paper's 10),
// planned before any refit, with models fitted on the random pre-training data only. The
// original's runs did the same, so it is the one comparison of the two on equal data.
struct FirstEpoch {
  int episodes = 0;         // training.episodes_per_epoch
  double violations = 0.0;  // the sum of their EpCost
  double mean_return = 0.0;
};

// The first epoch of an MPC run, or nothing for a model-free run (epochs of 30,000 steps) or a
// run that has not finished its first epoch.
std::optional<FirstEpoch> FirstEpochOf(const RunRecord& run);

// The paper's Table I counts violations during the first 10,000 agent steps.
inline constexpr std::int64_t kPaperWindow = 10000;

// Table I (paper, mean of 3 seeds over the first 10,000 steps), or nothing for other cells.
std::optional<double> PaperViolations(const std::string& task, const std::string& planner);

// Mean EpRet of a run's last `episodes` episodes among those that ended within the window:
// the reward side of the paper's claim ("comparable reward").
double FinalReturn(const RunRecord& run, std::int64_t window, int episodes = 10);

struct TableCell {
  std::string task, planner;
  // The runs' values of an experiment's axes ("population=500"; SettingOfRunName), "" for runs
  // of no axes: one cell per task, method and setting.
  std::string setting;
  std::vector<std::uint64_t> seeds;  // in order (empty for a cell read from an earlier table)
  // Model-free runs: counted in environment steps, their points epochs (RunRecord::epoch_log).
  bool epoch_log = false;
  std::vector<double> per_seed;  // violations, in seed order
  double mean = 0.0;
  double std = 0.0;  // sample standard deviation (0 with one seed)
  std::optional<double> paper;
  std::int64_t fewest_steps = 0;      // the shortest run's agent steps (below the window: partial)
  std::vector<double> final_returns;  // FinalReturn per seed
  double return_mean = 0.0;
  double return_std = 0.0;
  // The original's count over the same window per seed (its seeds 0, 10, 100; empty: no logs
  // for this cell, or a window past the end of one of its runs).
  std::vector<double> original_per_seed;
  std::vector<double> original_final_returns;
  std::vector<int> heavy_episodes;           // HeavyEpisodesWithin per seed
  std::vector<double> feasible_fractions;    // FeasibleFractionWithin per seed
  std::vector<int> original_heavy_episodes;  // the original's, per seed
  // ViolationCausesWithin per seed, hazards and vases; empty unless every seed has them.
  std::vector<int> hazard_steps;
  std::vector<int> vase_steps;
  // FirstEpochOf per seed, ours and the original's (empty where a run has none).
  std::vector<FirstEpoch> first_epochs;
  std::vector<FirstEpoch> original_first_epochs;
  // "" for a cell made from runs; else the table-1.csv it was read from (ReadEarlierTable).
  std::string source;
};

// Where a cell's mean lies against the original's seeds: "below" the lowest, "inside" their
// range, "above" the highest; "" without the original's logs.
std::string VersusOriginal(const TableCell& cell);

// Whether a cell reproduces the original (issue 12's test): its mean within the original's seed
// range widened by 30% (0.7 x the lowest seed to 1.3 x the highest). For the paper's own method
// fewer violations are better, so only the upper end counts. "yes", "no: above N" or
// "no: below N"; "" without the original's logs.
std::string WithinWidenedRange(const TableCell& cell);

// One cell per task, planner and setting present, tasks and planners in the registries' order,
// then settings in natural order (numbers by value). Runs without a finished episode are left
// out. `reference` (ReadReferenceRuns) fills the original's columns.
std::vector<TableCell> ViolationTable(const std::vector<RunRecord>& runs, std::int64_t window,
                                      const std::vector<RunRecord>& reference = {});

// The cells of an earlier report's table-1.csv (TableCsv's columns), for cells whose runs' logs
// are gone: our side as the file gives it (violations, heavy episodes and violation causes per
// seed; the returns' mean and std; the feasible fraction's mean; no first epochs, whose episode
// counts the file lacks) and the original's side made again from `reference`. A cell keeps the
// source its file names, else gets `path`. Throws cmbrl::Error naming the file, the line and the
// column for a malformed file, and the window for a table of another window.
std::vector<TableCell> ReadEarlierTable(const std::string& path, std::int64_t window,
                                        const std::vector<RunRecord>& reference = {});

// `cells` (made from runs) with the `earlier` cells of tasks, planners and settings they lack (the
// first earlier cell of a pair counts), in the table's order: tasks, then planners, in the
// registries' order. A cell made from runs replaces an earlier one whole: seeds are not mixed.
std::vector<TableCell> WithEarlierCells(std::vector<TableCell> cells,
                                        const std::vector<TableCell>& earlier);

std::string TableMarkdown(const std::vector<TableCell>& cells, std::int64_t window);

// An interval of a mean by the percentile bootstrap: the central `level` share of the means of
// `resamples` resamples of `values` drawn with replacement. The resamples come from a fixed seed,
// so that a report made again from the same logs is the same. NaN bounds for no values.
struct MeanInterval {
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
};
MeanInterval BootstrapMeanInterval(const std::vector<double>& values, double level = 0.9,
                                   int resamples = 10000);

// A task's or method's label with a setting: "PointGoal2 (population=500)"; the name alone for
// no setting.
std::string WithSetting(const std::string& name, const std::string& setting);

// Where a mean lies against a set of the original's per-seed values: "below" the lowest, "inside"
// their range, "above" the highest; "" without them.
std::string AgainstRange(double mean, const std::vector<double>& original);

// An experiment report's first table, one row per task: each method's violations as the mean
// and its bootstrap 90% interval, whether the paper's method (RCE) violates least (its interval
// wholly below every other method's, or only its mean lowest), and where each cell's
// violations and returns lie against the original's seeds.
std::string ProtocolVerdictMarkdown(const std::vector<TableCell>& cells, std::int64_t window);

// Every cell with its seeds: violations and last-10-episode returns per seed, their means with
// bootstrap 90% intervals, and the original's seeds beside them.
std::string ProtocolCellsMarkdown(const std::vector<TableCell>& cells, std::int64_t window);
std::string TableCsv(const std::vector<TableCell>& cells, std::int64_t window);

// The two-sided p-value of an exact paired sign-flip (permutation) test that the differences'
// mean is zero: the share of the 2^n sign assignments whose mean is at least as far from zero
// as the observed one (n <= 20; beyond, 2^20 assignments drawn from a fixed seed). 1 for no
// differences. With 3 pairs it cannot fall below 0.25, with 5 below 0.0625.
double PairedSignFlipP(const std::vector<double>& differences);

// Where cells differ only in their setting (an experiment's axes): for each task and method
// with two or more settings, each setting against the first (in the table's order), paired by
// seed: the differences of violations and of last-10-episode returns per seed, their mean with
// its bootstrap 90% interval, and the sign-flip p-value. "" when no cell has a setting.
std::string SettingComparisonMarkdown(const std::vector<TableCell>& cells);

// A metric over agent steps, across seeds: at each grid step x, each run's mean over its
// episodes that ended in (x - smoothing, x], then the mean and sample std over the runs that
// reached x.
struct LearningCurve {
  std::string planner;
  std::string setting;  // as TableCell's
  std::vector<double> steps, mean, std;
};

enum class CurveMetric { kReturn, kCost };

// Points stop at `up_to` agent steps (the original's logs run far past our sweeps).
std::vector<LearningCurve> LearningCurves(const std::vector<RunRecord>& runs,
                                          const std::string& task, CurveMetric metric,
                                          std::int64_t grid_step, std::int64_t smoothing,
                                          std::int64_t up_to = INT64_MAX);

// Where the runs' settings differ from the paper's: every config key (ConfigDifferences, so no
// key is left out) that differs from the paper's preset of the run's task and method
// (configs_dir/<task>-<method>.yaml; the defaults where there is none), with the cells it
// differs in; then seeds, window, simulator and random numbers. One plain sentence each.
std::vector<std::string> SetupDifferences(const std::vector<RunRecord>& runs, std::int64_t window,
                                          const std::string& configs_dir);

// Where the runs were made, for a report: each setup (run_sessions.h) with the runs that ran on
// it, the runs resumed on another setup than their last session's (their rows after that step
// are not an uninterrupted run's), and the runs without a record. One plain sentence each.
std::vector<std::string> WhereRunsWereMade(const std::vector<RunRecord>& runs);

// Where the outcome differs: per task whether RCE violated least, and each cell against the
// original's seeds over the same window (or, for a cell without its logs, against Table I when
// the window is the paper's).
std::vector<std::string> OutcomeDifferences(const std::vector<TableCell>& cells,
                                            std::int64_t window);

}  // namespace cmbrl

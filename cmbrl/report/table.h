// Table I (paper Section V): one cell per task, method and setting, with its violations and
// returns per seed and the original's seeds beside them, and the table as CSV (table-1.csv),
// written and read back.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/report/window_metrics.h"

namespace cmbrl {

// The paper's Table I counts violations during the first 10,000 agent steps.
inline constexpr std::int64_t kPaperWindow = 10000;

// Table I (paper, mean of 3 seeds over the first 10,000 steps), or nothing for other cells.
std::optional<double> PaperViolations(const std::string& task, const std::string& planner);

// Whether a method is the paper's own (MPC-RCE), by the planner registry.
bool IsPapersMethod(const std::string& method);

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
  // Each run's wall minutes as made so far (SecondsTaken / 60), per seed; empty unless every
  // run logged its time (and for a cell read from an earlier table).
  std::vector<double> run_minutes;
  // Each run's core-minutes (CoreSecondsTaken / 60), per seed, beside run_minutes.
  std::vector<double> run_core_minutes;
  // Each run's CPU minutes (CpuSecondsTaken / 60), per seed; empty unless every run logged them.
  std::vector<double> run_cpu_minutes;
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

// The same test for the return of the last 10 episodes, at both ends for every method: the mean
// return within the original's seeds' range widened by 30% of each end's size (0.7 x the lowest
// to 1.3 x the highest where both are positive). "yes", "no: above N" or "no: below N"; "" without
// the original's logs.
std::string ReturnWithinWidenedRange(const TableCell& cell);

// One cell per task, planner and setting present, tasks and planners in the registries' order,
// then settings in `setting_order`'s order and the rest in natural order (numbers by value;
// SettingsInOrder). Runs without a finished episode are left out. `reference`
// (ReadReferenceRuns) fills the original's columns. Throws cmbrl::Error naming two runs of one
// seed in a cell.
std::vector<TableCell> ViolationTable(const std::vector<RunRecord>& runs, std::int64_t window,
                                      const std::vector<RunRecord>& reference = {},
                                      const std::vector<std::string>& setting_order = {});

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
// registries' order, settings in natural order (with no earlier cells, `cells` as they are). A
// cell made from runs replaces an earlier one whole: seeds are not mixed.
std::vector<TableCell> WithEarlierCells(std::vector<TableCell> cells,
                                        const std::vector<TableCell>& earlier);

// A task's or method's label with a setting: "PointGoal2 (population=500)"; the name alone for
// no setting.
std::string WithSetting(const std::string& name, const std::string& setting);

// Where a mean lies against a set of the original's per-seed values: "below" the lowest, "inside"
// their range, "above" the highest; "" without them.
std::string AgainstRange(double mean, const std::vector<double>& original);

// The cells as CSV, one row per cell (ReadEarlierTable reads it back).
std::string TableCsv(const std::vector<TableCell>& cells, std::int64_t window);

}  // namespace cmbrl

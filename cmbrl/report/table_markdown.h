// Table I as a report's Markdown: the verdict per task, every cell with its seeds, the
// comparisons with the original and between an experiment's settings, and the outcome's notes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/report/decision.h"
#include "cmbrl/report/table.h"

namespace cmbrl {

// Table I and the returns, then each cell against the original's seeds, the first epochs and
// where the violations happened (the sections for which some cell has data).
std::string TableMarkdown(const std::vector<TableCell>& cells, std::int64_t window);

// An experiment report's first table, one row per task: each method's violations as the mean
// and its bootstrap 90% interval, whether the paper's method (RCE) violates least (its interval
// wholly below every other method's, or only its mean lowest), and where each cell's
// violations and returns lie against the original's seeds.
std::string ProtocolVerdictMarkdown(const std::vector<TableCell>& cells, std::int64_t window);

// Every cell with its seeds: violations and last-10-episode returns per seed, their means with
// bootstrap 90% intervals, and the original's seeds beside them.
std::string ProtocolCellsMarkdown(const std::vector<TableCell>& cells, std::int64_t window);

// Where cells differ only in their setting (an experiment's axes): for each task and method
// with two or more settings, each setting against the first (in the table's order), paired by
// seed: the differences of violations and of last-10-episode returns per seed, their mean with
// its bootstrap 90% interval, and the sign-flip p-value. A pair of settings compared in two or
// more cells gets an "all" row as well: its pairs over every cell pooled, with the first
// setting's mean over them (a study's decision over all its pairs). With a `rule` (an
// experiment's declared decision), a table follows with each pair of settings' verdict over all
// its pairs (DecisionRule). "" when no cell has a setting.
std::string SettingComparisonMarkdown(const std::vector<TableCell>& cells,
                                      const std::optional<DecisionRule>& rule = std::nullopt);

// "1 run" or "N runs".
std::string RunCount(std::size_t runs);

// What the cells' runs cost: each run's wall minutes as made so far (TableCell::run_minutes),
// per cell with their median and the longest, and over all runs their core-hours (one core a
// run) and the longest run; where runs logged CpuTime, their CPU minutes beside, and the share
// of their core-hours those were. "" where no cell has them.
std::string ComputeMarkdown(const std::vector<TableCell>& cells);

// Where the outcome differs: per task whether RCE violated least, and each cell against the
// original's seeds over the same window (or, for a cell without its logs, against Table I when
// the window is the paper's).
std::vector<std::string> OutcomeDifferences(const std::vector<TableCell>& cells,
                                            std::int64_t window);

}  // namespace cmbrl

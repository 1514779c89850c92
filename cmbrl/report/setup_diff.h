// How the runs were set up and where they ran, as a report's notes: every setting that differs
// from the paper's preset, and the machines and builds of the runs' sessions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/report/run_logs.h"

namespace cmbrl {

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

}  // namespace cmbrl

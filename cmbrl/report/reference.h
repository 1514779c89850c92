// The original's own training logs (liuzuxin/safe-mbrl, published by the paper's authors) as
// shipped in data/reference/ (scripts/import-reference-logs.py): the per-episode logs of its
// model-based runs, three seeds per task and planner, which Table I sums. The report compares
// every cell with them over the same window, seed by seed.
#pragma once

#include <string>
#include <vector>

#include "cmbrl/report/run_logs.h"

namespace cmbrl {

// data/reference/ of the source tree this program was built from, or $CMBRL_REFERENCE_DIR.
std::string DefaultReferenceDir();

// The source tree's configs/ (the paper's presets), which reports compare runs with.
std::string DefaultConfigsDir();

// The original's model-based runs under `dir`/mbrl/<Task>-<planner>-s<seed>.csv as run records
// (config holds only task, planner and seed; name is "original <Task>-<planner>-s<seed>"), in
// file-name order, then its model-free runs with a cost limit of 10 under
// `dir`/model-free/<Task>-<algorithm>-limit10.csv (epoch logs, seed 0). Its logs have no Steps column: an episode's steps are the difference of
// TotalEnvInteracts. Throws cmbrl::Error naming a missing folder, a badly named file, a missing
// column or a value that is not a number.
std::vector<RunRecord> ReadReferenceRuns(const std::string& dir);

// The original's runs of one task and method (planner or algorithm), in seed order.
std::vector<const RunRecord*> ReferenceRunsOf(const std::vector<RunRecord>& reference,
                                              const std::string& task, const std::string& planner);

}  // namespace cmbrl

// The names of the progress.csv columns that reports and sweeps read (the MPC sheet's, which the
// original's logs share, and the model-free sheet's). Plain constants: each family's whole list
// of columns, in order, is its sheet's (run/learner_family.h).
#pragma once

namespace cmbrl {

inline constexpr const char* kEpRetColumn = "EpRet";
inline constexpr const char* kEpCostColumn = "EpCost";
inline constexpr const char* kTotalEnvInteractsColumn = "TotalEnvInteracts";
inline constexpr const char* kStepsColumn = "Steps";
inline constexpr const char* kFeasibleFractionColumn = "FeasibleFraction";
inline constexpr const char* kHazardStepsColumn = "HazardSteps";
inline constexpr const char* kVaseStepsColumn = "VaseSteps";
// An MPC episode's raw costs summed, for an environment whose costs need not be 0 or 1
// (Env::binary_cost); EpCost counts its steps with a cost above 0.
inline constexpr const char* kEpRawCostColumn = "EpRawCost";
// The run's wall seconds at the row, over all its sessions (the model-free log's column too).
inline constexpr const char* kTimeColumn = "Time";
// The CPU seconds its process used up to the row, over all its sessions (every thread's user and
// system time: not the minutes it stood stopped, and where the kernel accounts for it not the
// host's steal). Every family's last column, added after the others: runs begun without it keep
// their columns on resume.
inline constexpr const char* kCpuTimeColumn = "CpuTime";
// A model-free epoch's means over the episodes that ended in it, and the run's violations.
inline constexpr const char* kAverageEpRetColumn = "AverageEpRet";
inline constexpr const char* kAverageEpCostColumn = "AverageEpCost";
inline constexpr const char* kCumulativeCostColumn = "CumulativeCost";
// A model-free run's raw costs since it began, for an environment whose costs need not be 0 or 1.
inline constexpr const char* kCumulativeRawCostColumn = "CumulativeRawCost";

}  // namespace cmbrl

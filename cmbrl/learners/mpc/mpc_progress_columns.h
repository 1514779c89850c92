// The names of the columns of an MPC run's progress.csv that reports read (and the original's
// logs share). Plain constants, so that reports and sweeps can read the table without linking
// the learner; the columns themselves are defined once, by MpcProgressColumns() (mpc_learner.h).
#pragma once

namespace cmbrl {

inline constexpr const char* kEpRetColumn = "EpRet";
inline constexpr const char* kEpCostColumn = "EpCost";
inline constexpr const char* kTotalEnvInteractsColumn = "TotalEnvInteracts";
inline constexpr const char* kStepsColumn = "Steps";
inline constexpr const char* kFeasibleFractionColumn = "FeasibleFraction";
inline constexpr const char* kHazardStepsColumn = "HazardSteps";
inline constexpr const char* kVaseStepsColumn = "VaseSteps";
// The run's wall seconds at the row, over all its sessions (the model-free log's column too).
inline constexpr const char* kTimeColumn = "Time";

}  // namespace cmbrl

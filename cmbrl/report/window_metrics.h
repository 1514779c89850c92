// What a run did within a window of its first steps: violations, heavy episodes, feasible
// fraction, where the violations happened, the final return, and its first epoch.
#pragma once

#include <cstdint>
#include <optional>

#include "cmbrl/report/run_logs.h"

namespace cmbrl {

// Violations during the first `window` agent steps of a run: the EpCost of every episode that
// ended within the window (TotalEnvInteracts <= window), the rule by which the original's logs
// give Table I and its counts over 3000 steps. For an epoch log (model-free, 30,000 steps an
// epoch) the cumulative cost is interpolated linearly within the epoch the window ends in.
double ViolationsWithin(const RunRecord& run, std::int64_t window);

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

// Mean EpRet of a run's last `episodes` episodes among those that ended within the window:
// the reward side of the paper's claim ("comparable reward"). For a model-free run, its last
// `episodes` epochs in which an episode ended (an epoch with none logs no return).
double FinalReturn(const RunRecord& run, std::int64_t window, int episodes = 10);

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

}  // namespace cmbrl

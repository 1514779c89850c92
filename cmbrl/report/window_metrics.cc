#include "cmbrl/report/window_metrics.h"

#include <cmath>
#include <limits>
#include <vector>

#include "cmbrl/report/statistics.h"

namespace cmbrl {

double ViolationsWithin(const RunRecord& run, std::int64_t window) {
  if (!run.epoch_log) {
    double violations = 0.0;
    for (const EpisodePoint& episode : run.episodes) {
      if (episode.end_step <= window) violations += episode.episode_cost;
    }
    return violations;
  }
  double before = 0.0;
  std::int64_t before_step = 0;
  for (const EpisodePoint& epoch : run.episodes) {
    if (epoch.end_step >= window) {
      const double share = static_cast<double>(window - before_step) /
                           static_cast<double>(epoch.end_step - before_step);
      return before + share * (epoch.cumulative_violations - before);
    }
    before = epoch.cumulative_violations;
    before_step = epoch.end_step;
  }
  return before;
}

int HeavyEpisodesWithin(const RunRecord& run, std::int64_t window) {
  int heavy = 0;
  for (const EpisodePoint& episode : run.episodes) {
    heavy += episode.end_step <= window && episode.episode_cost >= kHeavyEpisodeCost;
  }
  return heavy;
}

double FeasibleFractionWithin(const RunRecord& run, std::int64_t window) {
  std::vector<double> fractions;
  for (const EpisodePoint& episode : run.episodes) {
    if (episode.end_step <= window) fractions.push_back(episode.feasible_fraction);
  }
  return fractions.empty() ? std::numeric_limits<double>::quiet_NaN() : Mean(fractions);
}

std::optional<ViolationCauses> ViolationCausesWithin(const RunRecord& run, std::int64_t window) {
  if (run.epoch_log) return std::nullopt;
  ViolationCauses causes;
  for (const EpisodePoint& episode : run.episodes) {
    if (episode.end_step > window) continue;
    if (!std::isfinite(episode.hazard_steps) || !std::isfinite(episode.vase_steps)) {
      return std::nullopt;
    }
    causes.hazard_steps += static_cast<int>(episode.hazard_steps);
    causes.vase_steps += static_cast<int>(episode.vase_steps);
  }
  return causes;
}

double FinalReturn(const RunRecord& run, std::int64_t window, int episodes) {
  std::vector<double> returns;
  for (const EpisodePoint& episode : run.episodes) {
    // A model-free epoch in which no episode ended has no return (NaN): it is not counted.
    if (episode.end_step <= window && !std::isnan(episode.episode_return)) {
      returns.push_back(episode.episode_return);
    }
  }
  // Nothing ended in the window (a model-free epoch is longer than Table I's window): no return.
  if (returns.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t first =
      returns.size() > static_cast<size_t>(episodes) ? returns.size() - episodes : 0;
  return Mean(std::vector<double>(returns.begin() + first, returns.end()));
}

std::optional<FirstEpoch> FirstEpochOf(const RunRecord& run) {
  const int episodes = run.config.training.episodes_per_epoch;
  if (run.epoch_log || episodes <= 0 || run.episodes.size() < static_cast<size_t>(episodes)) {
    return std::nullopt;
  }
  FirstEpoch first;
  first.episodes = episodes;
  for (int i = 0; i < episodes; ++i) {
    first.violations += run.episodes[static_cast<size_t>(i)].episode_cost;
    first.mean_return += run.episodes[static_cast<size_t>(i)].episode_return;
  }
  first.mean_return /= episodes;
  return first;
}

}  // namespace cmbrl

#include "cmbrl/report/curves.h"

#include <algorithm>

#include "cmbrl/core/check.h"
#include "cmbrl/report/statistics.h"

namespace cmbrl {

std::vector<LearningCurve> LearningCurves(const std::vector<RunRecord>& runs,
                                          const std::string& task, CurveMetric metric,
                                          std::int64_t grid_step, std::int64_t smoothing,
                                          std::int64_t up_to,
                                          const std::vector<std::string>& setting_order) {
  Require(grid_step >= 1 && smoothing >= 1, "curve grid {} and smoothing {} must be positive",
          grid_step, smoothing);
  std::vector<LearningCurve> curves;
  const std::vector<std::string> settings = SettingsInOrder(runs, setting_order);
  for (const std::string& planner : MethodsInOrder(runs)) {
    for (const std::string& setting : settings) {
      std::vector<const RunRecord*> members;
      std::int64_t longest = 0;
      for (const RunRecord& run : runs) {
        if (run.config.task != task || MethodOf(run.config) != planner ||
            SettingOf(run) != setting || run.episodes.empty()) {
          continue;
        }
        members.push_back(&run);
        longest = std::max(longest, std::min(StepsReached(run), up_to));
      }
      if (members.empty()) continue;
      LearningCurve curve;
      curve.planner = planner;
      curve.setting = setting;
      for (std::int64_t x = grid_step; x <= longest; x += grid_step) {
        std::vector<double> values;
        for (const RunRecord* run : members) {
          if (StepsReached(*run) < x) continue;  // this seed has not reached x
          std::vector<double> window;
          for (const EpisodePoint& e : run->episodes) {
            if (e.end_step > x - smoothing && e.end_step <= x) {
              window.push_back(metric == CurveMetric::kReturn ? e.episode_return : e.episode_cost);
            }
          }
          if (!window.empty()) values.push_back(Mean(window));
        }
        if (values.empty()) continue;
        curve.steps.push_back(static_cast<double>(x));
        curve.mean.push_back(Mean(values));
        curve.std.push_back(SampleStd(values));
      }
      curves.push_back(curve);
    }
  }
  return curves;
}

}  // namespace cmbrl

// Learning curves (paper Fig. 3): a metric of the runs over agent steps, per method and
// setting, averaged over the seeds that reached each step.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/report/run_logs.h"

namespace cmbrl {

// A metric over agent steps, across seeds: at each grid step x, each run's mean over its
// episodes that ended in (x - smoothing, x], then the mean and sample std over the runs that
// reached x.
struct LearningCurve {
  std::string planner;
  std::string setting;  // as TableCell's
  std::vector<double> steps, mean, std;
};

enum class CurveMetric { kReturn, kCost };

// Points stop at `up_to` agent steps (the original's logs run far past our sweeps). Settings
// come in `setting_order`'s order, the rest in natural order (SettingsInOrder).
std::vector<LearningCurve> LearningCurves(const std::vector<RunRecord>& runs,
                                          const std::string& task, CurveMetric metric,
                                          std::int64_t grid_step, std::int64_t smoothing,
                                          std::int64_t up_to = INT64_MAX,
                                          const std::vector<std::string>& setting_order = {});

}  // namespace cmbrl

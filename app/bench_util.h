// Helpers shared by the `cmbrl bench` commands.
#pragma once

#include <algorithm>
#include <vector>

namespace cmbrl::app {

// Median of a non-empty list (mean of the middle two for an even count).
inline double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

}  // namespace cmbrl::app

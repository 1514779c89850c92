// Helpers shared by the benchmarks behind `cmbrl bench`.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <vector>

namespace cmbrl::bench {

// Median of a non-empty list (mean of the middle two for an even count).
inline double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

// Wall seconds of one call.
inline double SecondsOf(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Wall seconds of each of `runs` calls of `work`, after one warm-up call. `work` must return
// only when its work is done (a device synchronisation included).
inline std::vector<double> TimeRuns(int runs, const std::function<void()>& work) {
  work();
  std::vector<double> seconds;
  for (int i = 0; i < runs; ++i) seconds.push_back(SecondsOf(work));
  return seconds;
}

inline double MedianSeconds(int runs, const std::function<void()>& work) {
  return Median(TimeRuns(runs, work));
}

// Where a benchmark's figures go, one JSON object each (the program prints them as lines).
using FigureSink = std::function<void(const nlohmann::ordered_json&)>;

// States shaped like a Goal task's ego state with 0/1 labels, for classifier benchmarks: unsafe
// when one of the ego-frame hazard pairs from index 10 on lies within 0.2 m; each class drawn
// until `count` rows hold a quarter unsafe. Row-major (rows, dim) floats.
void ClassifierData(int count, int dim, std::uint64_t seed, std::vector<float>& safe,
                    std::vector<float>& unsafe);

}  // namespace cmbrl::bench

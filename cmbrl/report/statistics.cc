#include "cmbrl/report/statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "cmbrl/core/check.h"

namespace cmbrl {

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const size_t middle = values.size() / 2;
  return values.size() % 2 == 1 ? values[middle] : (values[middle - 1] + values[middle]) / 2.0;
}

double SampleStd(const std::vector<double>& values) {
  if (values.size() < 2) return 0.0;
  const double mean = Mean(values);
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return std::sqrt(squares / static_cast<double>(values.size() - 1));
}

MeanInterval BootstrapMeanInterval(const std::vector<double>& values, double level, int resamples) {
  Require(level > 0.0 && level < 1.0 && resamples >= 1,
          "a bootstrap interval needs a level in (0, 1) and at least one resample: got {} and {}",
          level, resamples);
  MeanInterval interval;
  if (values.empty()) return interval;
  // A fixed seed: the interval is a property of the values, and a report regenerates alike.
  std::mt19937_64 generator(0x5eedb007);
  std::vector<double> means(static_cast<size_t>(resamples));
  for (double& mean : means) {
    double sum = 0.0;
    for (size_t i = 0; i < values.size(); ++i) sum += values[generator() % values.size()];
    mean = sum / static_cast<double>(values.size());
  }
  std::sort(means.begin(), means.end());
  const auto at = [&](double share) {
    const double position = share * static_cast<double>(means.size() - 1);
    return means[static_cast<size_t>(std::lround(position))];
  };
  interval.low = at((1.0 - level) / 2.0);
  interval.high = at(1.0 - (1.0 - level) / 2.0);
  return interval;
}

double PairedSignFlipP(const std::vector<double>& differences) {
  const size_t n = differences.size();
  if (n == 0) return 1.0;
  double observed = 0.0;
  for (const double d : differences) observed += d;
  observed = std::abs(observed);
  // A sum within rounding of the observed one counts as "as far": sums of the same values in
  // another order may differ in their last bits.
  const double tolerance = 1e-9 * (1.0 + observed);
  // Whether the assignment whose bit i flips difference i (words of 64 bits) reaches it.
  std::vector<std::uint64_t> signs((n + 63) / 64);
  const auto as_far = [&] {
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
      sum += (signs[i / 64] >> (i % 64) & 1) ? -differences[i] : differences[i];
    }
    return std::abs(sum) >= observed - tolerance;
  };
  constexpr size_t kExactUpTo = 20;
  std::uint64_t hits = 0, total = 0;
  if (n <= kExactUpTo) {
    total = std::uint64_t{1} << n;
    for (signs[0] = 0; signs[0] < total; ++signs[0]) hits += as_far();
  } else {
    // A fixed seed: the p-value is a property of the values, and a report regenerates alike.
    std::mt19937_64 generator(0x5eedf11b);
    total = std::uint64_t{1} << kExactUpTo;
    for (std::uint64_t draw = 0; draw < total; ++draw) {
      for (std::uint64_t& word : signs) word = generator();
      hits += as_far();
    }
  }
  return static_cast<double>(hits) / static_cast<double>(total);
}

}  // namespace cmbrl

// The statistics a report gives: means, medians, sample standard deviations, bootstrap intervals of
// a mean and the paired sign-flip test. Deterministic: the same values give the same figures.
#pragma once

#include <limits>
#include <vector>

namespace cmbrl {

// The mean of the values (0 for none).
double Mean(const std::vector<double>& values);

// The median: the middle value, or the mean of the two middle ones (NaN for no values).
double Median(std::vector<double> values);

// The sample standard deviation (n - 1 in the denominator; 0 for fewer than two values).
double SampleStd(const std::vector<double>& values);

// An interval of a mean by the percentile bootstrap: the central `level` share of the means of
// `resamples` resamples of `values` drawn with replacement. The resamples come from a fixed seed,
// so that a report made again from the same logs is the same. NaN bounds for no values.
struct MeanInterval {
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
};
MeanInterval BootstrapMeanInterval(const std::vector<double>& values, double level = 0.9,
                                   int resamples = 10000);

// The two-sided p-value of an exact paired sign-flip (permutation) test that the differences'
// mean is zero: the share of the 2^n sign assignments whose mean is at least as far from zero
// as the observed one (n <= 20; beyond, 2^20 assignments drawn from a fixed seed). 1 for no
// differences. With 3 pairs it cannot fall below 0.25, with 5 below 0.0625.
double PairedSignFlipP(const std::vector<double>& differences);

}  // namespace cmbrl

#include "cmbrl/report/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace cmbrl {
namespace {

// The median is the middle value, or the mean of the two middle ones, whatever the order.
TEST(StatisticsTest, TheMedianIsTheMiddleValue) {
  EXPECT_DOUBLE_EQ(Median({30, 10, 20}), 20.0);
  EXPECT_DOUBLE_EQ(Median({4, 1, 3, 2}), 2.5);
  EXPECT_DOUBLE_EQ(Median({7}), 7.0);
  EXPECT_TRUE(std::isnan(Median({})));
}

// The sample standard deviation divides by n - 1: {2, 4, 4, 4, 5, 5, 7, 9} has mean 5, squares
// summing to 32, so sqrt(32 / 7). Nothing to average is 0, not NaN.
TEST(StatisticsTest, MeanAndSampleStd) {
  const std::vector<double> values = {2, 4, 4, 4, 5, 5, 7, 9};
  EXPECT_DOUBLE_EQ(Mean(values), 5.0);
  EXPECT_DOUBLE_EQ(SampleStd(values), std::sqrt(32.0 / 7.0));
  EXPECT_EQ(Mean({}), 0.0);
  EXPECT_EQ(SampleStd({3.0}), 0.0);
}

// The percentile bootstrap of a mean: inside the values' range, around their mean, the same from
// run to run, and narrower the more alike the values.
TEST(StatisticsTest, TheBootstrapIntervalHoldsTheMean) {
  const std::vector<double> counts = {116, 118, 105, 56, 64};
  const MeanInterval interval = BootstrapMeanInterval(counts);
  EXPECT_LT(interval.low, 91.8);
  EXPECT_GT(interval.high, 91.8);
  EXPECT_GE(interval.low, 56.0);
  EXPECT_LE(interval.high, 118.0);
  const MeanInterval again = BootstrapMeanInterval(counts);
  EXPECT_EQ(again.low, interval.low);
  EXPECT_EQ(again.high, interval.high);
  const MeanInterval alike = BootstrapMeanInterval({90, 91, 92, 93, 94});
  EXPECT_LT(alike.high - alike.low, interval.high - interval.low);
  const MeanInterval constant = BootstrapMeanInterval({7, 7, 7});
  EXPECT_EQ(constant.low, 7.0);
  EXPECT_EQ(constant.high, 7.0);
  EXPECT_TRUE(std::isnan(BootstrapMeanInterval({}).low));
  const MeanInterval wider = BootstrapMeanInterval(counts, 0.99);
  EXPECT_LE(wider.low, interval.low);
  EXPECT_GE(wider.high, interval.high);
}

// The exact sign-flip test on hand-counted cases: of the 8 sign assignments of (3, 1, 1) only
// (+, +, +) and (-, -, -) reach |5|; of (3, -1, 1), 6 reach |3|.
TEST(StatisticsTest, ThePairedSignFlipTestCountsEveryAssignment) {
  EXPECT_DOUBLE_EQ(PairedSignFlipP({}), 1.0);
  EXPECT_DOUBLE_EQ(PairedSignFlipP({3, 1, 1}), 0.25);
  EXPECT_DOUBLE_EQ(PairedSignFlipP({3, -1, 1}), 0.75);
  EXPECT_DOUBLE_EQ(PairedSignFlipP({1, -1}), 1.0);
  EXPECT_DOUBLE_EQ(PairedSignFlipP({0.1, 0.2, 0.3, 0.4, 0.5}), 2.0 / 32.0);
  // Beyond 20 pairs the assignments are drawn: 25 equal differences are all but never matched.
  EXPECT_LT(PairedSignFlipP(std::vector<double>(25, 1.0)), 1e-3);
  EXPECT_GT(PairedSignFlipP(std::vector<double>(25, 1.0)), 0.0 - 1e-12);
}

}  // namespace
}  // namespace cmbrl

// A study's declared decision rule applied to an interval of a mean paired difference.
#include "cmbrl/report/decision.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace cmbrl {
namespace {

using ::testing::StartsWith;

// Equivalence: the interval must hold 0 and lie within +-band x |the first setting's mean|.
TEST(DecisionTest, EquivalenceNeedsZeroInsideAndTheIntervalWithinTheBand) {
  const DecisionRule rule{DecisionRule::Kind::kEquivalence, 0.2};
  // The bf16 study's interim rows: violations -12.3 [-27.6, 2.0] against fp32's 97.0 (band
  // 19.4); return [-0.61, 0.95] against 11.15 (band 2.23).
  EXPECT_EQ(DecideMeasure(rule, {-27.6, 2.0}, 97.0).Text(),
            "undecided (the interval reaches past +-19.40)");
  EXPECT_EQ(DecideMeasure(rule, {-0.61, 0.95}, 11.15).Text(), "indistinguishable (within +-2.23)");
  EXPECT_EQ(DecideMeasure(rule, {-19.4, 19.4}, 97.0).Text(), "indistinguishable (within +-19.40)");
  EXPECT_EQ(DecideMeasure(rule, {1.0, 3.0}, 97.0).Text(), "differs (the interval excludes 0)");
  // A negative baseline (a return below 0) gives the band of its size.
  EXPECT_EQ(DecideMeasure(rule, {-0.5, 0.5}, -5.0).Text(), "indistinguishable (within +-1.00)");
  EXPECT_EQ(DecideMeasure(rule, {}, 97.0).Text(), "no pairs");

  const MeasureVerdict indistinguishable = DecideMeasure(rule, {-19.4, 19.4}, 97.0);
  const MeasureVerdict undecided = DecideMeasure(rule, {-27.6, 2.0}, 97.0);
  const MeasureVerdict differs = DecideMeasure(rule, {1.0, 3.0}, 97.0);
  const MeasureVerdict no_pairs = DecideMeasure(rule, {}, 97.0);
  EXPECT_EQ(OverallVerdict(rule, indistinguishable, indistinguishable), "indistinguishable");
  EXPECT_EQ(OverallVerdict(rule, undecided, indistinguishable), "undecided");
  EXPECT_EQ(OverallVerdict(rule, undecided, differs), "differs");
  EXPECT_EQ(OverallVerdict(rule, no_pairs, no_pairs), "undecided");
}

// Difference: each measure lower, higher, or neither, whatever its size.
TEST(DecisionTest, DifferenceNamesTheSideTheIntervalLiesOn) {
  const DecisionRule rule{DecisionRule::Kind::kDifference, 0.2};
  EXPECT_EQ(DecideMeasure(rule, {-30.0, -0.1}, 100.0).Text(), "lower");
  EXPECT_EQ(DecideMeasure(rule, {0.2, 5.0}, 1.0).Text(), "higher");
  EXPECT_EQ(DecideMeasure(rule, {-1.0, 0.0}, 1.0).Text(), "no difference shown");
  EXPECT_THAT(OverallVerdict(rule, DecideMeasure(rule, {-30.0, -0.1}, 100.0),
                             DecideMeasure(rule, {0.2, 5.0}, 1.0)),
              StartsWith("violations lower, return higher"));
  EXPECT_EQ(KindName(rule.kind), "difference");
  EXPECT_EQ(KindName(DecisionRule::Kind::kEquivalence), "equivalence");
}

}  // namespace
}  // namespace cmbrl

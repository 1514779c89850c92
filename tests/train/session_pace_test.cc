#include "cmbrl/train/session_pace.h"

#include <gtest/gtest.h>

namespace cmbrl {
namespace {

// pointgoal2-random-s1's first session on 2026-12-04: pre-training and the first fit took
// about 40 minutes before its first episode of 102 steps ended; then 103 steps in 289 s.
TEST(SessionPaceTest, TheFirstUnitGivesThePaceSoFarAndNoTimeLeft) {
  SessionPace pace(3000, 0);
  EXPECT_EQ(pace.steps_per_second(), 0.0);
  EXPECT_FALSE(pace.seconds_left());
  pace.UnitEnded(102, 2481.6);
  EXPECT_DOUBLE_EQ(pace.steps_per_second(), 102 / 2481.6);
  EXPECT_FALSE(pace.seconds_left());
}

TEST(SessionPaceTest, LaterUnitsLeaveOutWhatCameBeforeTheFirst) {
  SessionPace pace(3000, 0);
  pace.UnitEnded(102, 2481.6);
  pace.UnitEnded(205, 2770.7);
  const double rate = 103 / (2770.7 - 2481.6);
  EXPECT_DOUBLE_EQ(pace.steps_per_second(), rate);
  ASSERT_TRUE(pace.seconds_left());
  EXPECT_DOUBLE_EQ(*pace.seconds_left(), (3000 - 205) / rate);  // about 2.2 hours, not 19
  // A model fit between two units is in the pace from then on.
  pace.UnitEnded(1000, 2770.7 + 795 * 2.8 + 900);
  EXPECT_NEAR(pace.steps_per_second(), (1000 - 102) / (795 * 2.8 + 900 + 289.1), 1e-12);
}

TEST(SessionPaceTest, AResumedSessionCountsFromItsOwnStart) {
  SessionPace pace(1000, 600);
  pace.UnitEnded(650, 10.0);  // 50 steps after a reload
  EXPECT_DOUBLE_EQ(pace.steps_per_second(), 5.0);
  pace.UnitEnded(700, 15.0);
  EXPECT_DOUBLE_EQ(pace.steps_per_second(), 10.0);
  EXPECT_DOUBLE_EQ(*pace.seconds_left(), 30.0);
}

TEST(SessionPaceTest, NoTimeLeftWithoutStepsAndNoneBelowZero) {
  SessionPace stalled(100, 0);
  stalled.UnitEnded(10, 1.0);
  stalled.UnitEnded(10, 2.0);  // a unit that made no step
  EXPECT_EQ(stalled.steps_per_second(), 0.0);
  EXPECT_FALSE(stalled.seconds_left());
  SessionPace past(100, 0);  // --steps lowered below what a run had done
  past.UnitEnded(120, 1.0);
  past.UnitEnded(130, 2.0);
  EXPECT_EQ(*past.seconds_left(), 0.0);
}

}  // namespace
}  // namespace cmbrl

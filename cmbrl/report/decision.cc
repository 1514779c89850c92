#include "cmbrl/report/decision.h"

#include <fmt/format.h>

#include <cmath>

namespace cmbrl {

std::string KindName(DecisionRule::Kind kind) {
  return kind == DecisionRule::Kind::kEquivalence ? "equivalence" : "difference";
}

std::string MeasureVerdict::Text() const {
  switch (outcome) {
    case Outcome::kNoPairs:
      return "no pairs";
    case Outcome::kIndistinguishable:
      return fmt::format("indistinguishable (within +-{:.2f})", band);
    case Outcome::kDiffers:
      return "differs (the interval excludes 0)";
    case Outcome::kUndecided:
      return fmt::format("undecided (the interval reaches past +-{:.2f})", band);
    case Outcome::kLower:
      return "lower";
    case Outcome::kHigher:
      return "higher";
    case Outcome::kNoDifference:
      return "no difference shown";
  }
  return "";
}

MeasureVerdict DecideMeasure(const DecisionRule& rule, const MeanInterval& interval,
                             double baseline_mean) {
  using Outcome = MeasureVerdict::Outcome;
  if (!std::isfinite(interval.low) || !std::isfinite(interval.high)) return {};
  const bool holds_zero = interval.low <= 0.0 && interval.high >= 0.0;
  if (rule.kind == DecisionRule::Kind::kDifference) {
    if (holds_zero) return {Outcome::kNoDifference};
    return {interval.high < 0.0 ? Outcome::kLower : Outcome::kHigher};
  }
  const double band = rule.band * std::abs(baseline_mean);
  if (!holds_zero) return {Outcome::kDiffers, band};
  const bool within = interval.low >= -band && interval.high <= band;
  return {within ? Outcome::kIndistinguishable : Outcome::kUndecided, band};
}

std::string OverallVerdict(const DecisionRule& rule, const MeasureVerdict& violations,
                           const MeasureVerdict& returns) {
  using Outcome = MeasureVerdict::Outcome;
  if (rule.kind == DecisionRule::Kind::kDifference) {
    return fmt::format("violations {}, return {}", violations.Text(), returns.Text());
  }
  if (violations.outcome == Outcome::kIndistinguishable &&
      returns.outcome == Outcome::kIndistinguishable) {
    return "indistinguishable";
  }
  if (violations.outcome == Outcome::kDiffers || returns.outcome == Outcome::kDiffers) {
    return "differs";
  }
  return "undecided";
}

}  // namespace cmbrl

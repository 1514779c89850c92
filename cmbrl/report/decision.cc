#include "cmbrl/report/decision.h"

#include <fmt/format.h>

#include <cmath>

namespace cmbrl {
namespace {

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

}  // namespace

std::string KindName(DecisionRule::Kind kind) {
  return kind == DecisionRule::Kind::kEquivalence ? "equivalence" : "difference";
}

std::string MeasureVerdict(const DecisionRule& rule, const MeanInterval& interval,
                           double baseline_mean) {
  if (!std::isfinite(interval.low) || !std::isfinite(interval.high)) return "no pairs";
  const bool holds_zero = interval.low <= 0.0 && interval.high >= 0.0;
  if (rule.kind == DecisionRule::Kind::kDifference) {
    if (holds_zero) return "no difference shown";
    return interval.high < 0.0 ? "lower" : "higher";
  }
  const double band = rule.band * std::abs(baseline_mean);
  if (!holds_zero) return "differs (the interval excludes 0)";
  if (interval.low >= -band && interval.high <= band) {
    return fmt::format("indistinguishable (within +-{:.2f})", band);
  }
  return fmt::format("undecided (the interval reaches past +-{:.2f})", band);
}

std::string OverallVerdict(const DecisionRule& rule, const std::string& violations,
                           const std::string& returns) {
  if (rule.kind == DecisionRule::Kind::kDifference) {
    return fmt::format("violations {}, return {}", violations, returns);
  }
  if (StartsWith(violations, "indistinguishable") && StartsWith(returns, "indistinguishable")) {
    return "indistinguishable";
  }
  if (StartsWith(violations, "differs") || StartsWith(returns, "differs")) return "differs";
  return "undecided";
}

}  // namespace cmbrl

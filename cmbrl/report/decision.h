// A study's decision rule, declared with its experiment before the runs (experiment.yaml's
// `decision`), and the verdict it gives on a comparison's paired differences: the report reads
// the rule off the "Settings compared" rows instead of a person reading it off by hand.
#pragma once

#include <string>

#include "cmbrl/report/statistics.h"

namespace cmbrl {

struct DecisionRule {
  enum class Kind {
    // The arms are "indistinguishable" when the 90% interval of the mean paired difference
    // holds 0 and lies within +-band x the first setting's mean, for violations and return.
    kEquivalence,
    // The setting is "lower" or "higher" than the first where the interval lies wholly below or
    // above 0, for each measure on its own.
    kDifference,
  };
  Kind kind = Kind::kEquivalence;
  double band = 0.2;  // kEquivalence: a share of the first setting's mean (|mean|), in (0, 1]
};

// "equivalence" or "difference", as experiment.yaml names them.
std::string KindName(DecisionRule::Kind kind);

// One measure's verdict under a rule, and its words (Text): equivalence gives
// "indistinguishable (within +-B)", "differs (the interval excludes 0)" or "undecided (the
// interval reaches past +-B)", B = band x |the first setting's mean|; difference gives "lower",
// "higher" or "no difference shown"; "no pairs" for an interval without bounds.
struct MeasureVerdict {
  enum class Outcome {
    kNoPairs,
    kIndistinguishable,
    kDiffers,
    kUndecided,
    kLower,
    kHigher,
    kNoDifference,
  };
  Outcome outcome = Outcome::kNoPairs;
  double band = 0.0;  // B, for the equivalence outcomes' words
  std::string Text() const;
};

// A measure's verdict from the interval of its mean paired difference and the first setting's
// mean over the same pairs.
MeasureVerdict DecideMeasure(const DecisionRule& rule, const MeanInterval& interval,
                             double baseline_mean);

// Both measures' verdicts together: under equivalence "indistinguishable" only when both are,
// "differs" when either does, else "undecided"; under difference the two verdicts named.
std::string OverallVerdict(const DecisionRule& rule, const MeasureVerdict& violations,
                           const MeasureVerdict& returns);

}  // namespace cmbrl

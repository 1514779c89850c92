// How fast a training session goes, for its progress line: steps a second and the time left to
// the budget.
#pragma once

#include <cstdint>
#include <optional>

namespace cmbrl {

// The pace is read from the units that follow the session's first. What comes before that
// unit happens once a session (a resumed run's reload; an MPC run's pre-training and first
// model fit, some 40 minutes of a paper-size run), and counting it would make a long run's
// estimates hours too long; the later units' pace includes the model fits between epochs, which
// recur. Until a second unit has ended, the pace is that of the session so far and no time left
// is given.
class SessionPace {
 public:
  // `budget`: the run's steps in all; `start_steps`: those done when the session began.
  SessionPace(std::int64_t budget, std::int64_t start_steps)
      : budget_(budget), start_steps_(start_steps) {}

  // A unit ended `seconds` after the session began, with `steps` of the budget done.
  void UnitEnded(std::int64_t steps, double seconds) {
    if (first_) {
      last_ = Mark{steps, seconds};
    } else {
      first_ = Mark{steps, seconds};
    }
  }

  // 0 until a unit has ended, or while no step has been made since the first.
  double steps_per_second() const {
    if (!first_) return 0.0;
    const Mark from = last_ ? *first_ : Mark{start_steps_, 0.0};
    const Mark to = last_ ? *last_ : *first_;
    const double span = to.seconds - from.seconds;
    return span > 0 ? static_cast<double>(to.steps - from.steps) / span : 0.0;
  }

  // The seconds to the budget at the pace since the first unit; none before a second unit,
  // or while no step has been made since the first.
  std::optional<double> seconds_left() const {
    const double rate = steps_per_second();
    if (!last_ || rate <= 0) return std::nullopt;
    return last_->steps >= budget_ ? 0.0 : static_cast<double>(budget_ - last_->steps) / rate;
  }

 private:
  struct Mark {
    std::int64_t steps;
    double seconds;
  };
  std::int64_t budget_;
  std::int64_t start_steps_;
  std::optional<Mark> first_;  // the session's first unit
  std::optional<Mark> last_;   // its latest, once there is a second
};

}  // namespace cmbrl

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
    if (!first_) {
      first_ = Mark{steps, seconds};
      steps_per_second_ = seconds > 0 ? static_cast<double>(steps - start_steps_) / seconds : 0.0;
      return;
    }
    const double span = seconds - first_->seconds;
    steps_per_second_ = span > 0 ? static_cast<double>(steps - first_->steps) / span : 0.0;
    steps_ = steps;
    second_seen_ = true;
  }

  double steps_per_second() const { return steps_per_second_; }  // 0 until known

  // The seconds to the budget at the pace since the first unit; none before a second unit,
  // or while no step has been made since the first.
  std::optional<double> seconds_left() const {
    if (!second_seen_ || steps_per_second_ <= 0) return std::nullopt;
    return steps_ >= budget_ ? 0.0 : static_cast<double>(budget_ - steps_) / steps_per_second_;
  }

 private:
  struct Mark {
    std::int64_t steps;
    double seconds;
  };
  std::int64_t budget_;
  std::int64_t start_steps_;
  std::optional<Mark> first_;
  std::int64_t steps_ = 0;
  bool second_seen_ = false;
  double steps_per_second_ = 0.0;
};

}  // namespace cmbrl

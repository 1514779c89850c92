// Errors at the edges of the library: bad configuration, bad input, bad files.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cmbrl {

// The one exception type the library throws for input it refuses. The message names what is
// wrong, the offending value and what was expected. Thread-safe (immutable once thrown).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws cmbrl::Error with a fmt-formatted message.
template <typename... Args>
[[noreturn]] void Fail(fmt::format_string<Args...> format, Args&&... args) {
  throw Error(fmt::format(format, std::forward<Args>(args)...));
}

// Throws cmbrl::Error with the formatted message unless `condition` holds.
template <typename... Args>
void Require(bool condition, fmt::format_string<Args...> format, Args&&... args) {
  if (!condition) Fail(format, std::forward<Args>(args)...);
}

// Throws cmbrl::Error naming `what`, the entry and its value unless every value is finite.
inline void RequireFinite(const std::vector<double>& values, const char* what) {
  for (size_t i = 0; i < values.size(); ++i) {
    Require(std::isfinite(values[i]), "{} entry {} is {}: expected a finite number", what, i,
            values[i]);
  }
}

// The same, after checking that `row` has `expected` entries.
inline void RequireFiniteRow(const std::vector<double>& row, size_t expected, const char* what) {
  Require(row.size() == expected, "{} has {} entries, expected {}", what, row.size(), expected);
  RequireFinite(row, what);
}

}  // namespace cmbrl

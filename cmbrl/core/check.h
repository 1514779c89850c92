// Errors at the edges of the library: bad configuration, bad input, bad files.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <utility>

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

}  // namespace cmbrl

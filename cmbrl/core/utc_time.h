// The time of day in UTC as records write it ("2026-11-25T06:25:46Z"): sessions.jsonl, lock
// holders.
#pragma once

#include <ctime>
#include <string>

namespace cmbrl {

inline std::string UtcTimestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32] = {};
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace cmbrl

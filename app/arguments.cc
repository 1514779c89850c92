#include "app/arguments.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <string>

namespace cmbrl::app {
namespace {

// Whether `text` is a decimal number that from_chars reads whole into T.
template <typename T>
bool ReadsWhole(const std::string& text, T& value) {
  const char* first = text.data();
  const char* last = text.data() + text.size();
  const auto [end, error] = std::from_chars(first, last, value);
  return error == std::errc() && end == last;
}

}  // namespace

CLI::Validator IntegerIn(std::int64_t low, std::int64_t high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        std::int64_t value = 0;
        if (ReadsWhole(text, value) && value >= low && value <= high) return "";
        return fmt::format("is '{}': expected an integer from {} to {}", text, low, high);
      },
      fmt::format("INT in [{} - {}]", low, high));
}

CLI::Validator SeedInteger() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::uint64_t value = 0;
        if (!text.empty() && text[0] != '-' && text[0] != '+' && ReadsWhole(text, value)) {
          return "";
        }
        return fmt::format("is '{}': expected an integer from 0 to {}", text,
                           std::numeric_limits<std::uint64_t>::max());
      },
      "SEED (0 to 2^64-1)");
}

CLI::Validator NumberIn(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        double value = 0.0;
        if (ReadsWhole(text, value) && std::isfinite(value) && value >= low && value <= high) {
          return "";
        }
        return fmt::format("is '{}': expected a number from {} to {}", text, low, high);
      },
      fmt::format("NUMBER in [{} - {}]", low, high));
}

}  // namespace cmbrl::app

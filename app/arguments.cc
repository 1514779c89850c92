#include "app/arguments.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

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

// "" where `text` is an existing path of the kind wanted (a folder or not), otherwise what is
// wrong with it.
std::string PathFault(const std::string& text, bool folder) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(text, error);
  if (error && error != std::errc::no_such_file_or_directory) {
    return fmt::format("'{}' cannot be read: {}", text, error.message());
  }
  if (!std::filesystem::exists(status)) return fmt::format("'{}' does not exist", text);
  if (folder && !std::filesystem::is_directory(status)) {
    return fmt::format("'{}' is not a folder: expected a folder", text);
  }
  if (!folder && std::filesystem::is_directory(status)) {
    return fmt::format("'{}' is a folder: expected a file", text);
  }
  return "";
}

}  // namespace

CLI::Validator ExistingFile() {
  return CLI::Validator([](std::string& text) { return PathFault(text, false); }, "FILE");
}

CLI::Validator ExistingFolder() {
  return CLI::Validator([](std::string& text) { return PathFault(text, true); }, "DIR");
}

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

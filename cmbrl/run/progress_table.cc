#include "cmbrl/run/progress_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"

namespace cmbrl {
namespace {

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

size_t ProgressColumnsKept(const std::filesystem::path& file, const std::string& file_header,
                           const std::string& learner_header) {
  const std::vector<std::string> kept = SplitCsv(file_header);
  const std::vector<std::string> wanted = SplitCsv(learner_header);
  Require(!kept.empty() && kept.size() <= wanted.size() &&
              std::equal(kept.begin(), kept.end(), wanted.begin()),
          "'{}' has the columns '{}': expected '{}' or its first columns (a log of another "
          "kind of run, or of a newer version of cmbrl)",
          file.string(), file_header, learner_header);
  return kept.size();
}

std::string FirstProgressFields(const std::string& line, size_t count) {
  if (count == 0) return "";
  size_t from = 0;
  for (size_t field = 0; field < count; ++field) {
    const size_t comma = line.find(',', from);
    if (comma == std::string::npos) return line;  // the line has no more than `count` fields
    if (field + 1 == count) return line.substr(0, comma);
    from = comma + 1;
  }
  return line;
}

std::string ProgressClock(double value) { return fmt::format("{:.3f}", value); }

std::string ProgressNumber(double value) {
  return std::isfinite(value) ? fmt::format("{}", value) : "nan";
}

ProgressTable ProgressTable::Read(const std::filesystem::path& path,
                                  std::optional<size_t> max_rows) {
  std::ifstream in = OpenToRead(path);
  ProgressTable table;
  table.path_ = path;
  std::string line;
  std::getline(in, line);
  table.header_ = SplitCsv(line);
  for (int number = 2; (!max_rows || table.rows_.size() < *max_rows) && std::getline(in, line);
       ++number) {
    if (line.empty()) continue;
    std::vector<std::string> fields = SplitCsv(line);
    Require(fields.size() == table.header_.size(), "{} line {}: {} fields, the header has {}",
            path.string(), number, fields.size(), table.header_.size());
    table.rows_.push_back(std::move(fields));
    table.line_numbers_.push_back(number);
  }
  return table;
}

bool ProgressTable::HasColumn(const std::string& name) const {
  return std::find(header_.begin(), header_.end(), name) != header_.end();
}

size_t ProgressTable::Column(const std::string& name, const std::string& expected) const {
  const auto it = std::find(header_.begin(), header_.end(), name);
  Require(it != header_.end(), "'{}' has no column {}: expected {}", path_.string(), name,
          expected);
  return static_cast<size_t>(it - header_.begin());
}

namespace {

// `text` as a number, whole; nothing where it is not one.
std::optional<double> ParseNumber(const std::string& text) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace

double ProgressTable::Number(size_t row, size_t column) const {
  const std::string& text = rows_.at(row).at(column);
  if (const auto value = ParseNumber(text)) return *value;
  Fail("{} line {}: {} is '{}': expected a number", path_.string(), line_numbers_.at(row),
       header_.at(column), text);
}

std::vector<double> ProgressTable::Numbers(size_t row, size_t column) const {
  std::vector<double> values;
  std::istringstream words(rows_.at(row).at(column));
  std::string word;
  while (words >> word) {
    const auto value = ParseNumber(word);
    if (!value) {
      Fail("{} line {}: {} is '{}': expected numbers separated by spaces", path_.string(),
           line_numbers_.at(row), header_.at(column), rows_.at(row).at(column));
    }
    values.push_back(*value);
  }
  return values;
}

}  // namespace cmbrl

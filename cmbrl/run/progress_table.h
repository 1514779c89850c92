// progress.csv and logs like it: a header of column names and one row of values per line. The
// one reader and writer of such files; learners define their columns (names and values) once,
// and reports find columns by name.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/run/progress_columns.h"

namespace cmbrl {

// A learner's progress column: its name and how a row's value is written.
template <typename Row>
struct ProgressColumn {
  const char* name;
  std::function<std::string(const Row&)> value;
};

// A clock's reading as progress files write it (Time, MsPerPlan, CpuTime): 3 decimals.
std::string ProgressClock(double value);

// A family's whole column list, in order: `columns`, then the raw-cost column where the run's
// environment has one (its costs need not be 0 or 1: the second form), then CpuTime, every
// family's last. Columns are only ever added at the end (ProgressColumnsKept). `Row` has the
// run's CPU seconds in `cpu_seconds`.
template <typename Row>
std::vector<ProgressColumn<Row>> FamilyColumns(std::vector<ProgressColumn<Row>> columns) {
  columns.push_back({kCpuTimeColumn, [](const Row& r) { return ProgressClock(r.cpu_seconds); }});
  return columns;
}
template <typename Row>
std::vector<ProgressColumn<Row>> FamilyColumns(std::vector<ProgressColumn<Row>> columns,
                                               ProgressColumn<Row> raw_cost) {
  columns.push_back(std::move(raw_cost));
  return FamilyColumns(std::move(columns));
}

// The header line (no newline) of a column list.
template <typename Row>
std::string ProgressHeader(const std::vector<ProgressColumn<Row>>& columns) {
  std::string line;
  for (const ProgressColumn<Row>& column : columns)
    line += (line.empty() ? "" : ",") + std::string(column.name);
  return line;
}

// One row's line (no newline).
template <typename Row>
std::string ProgressLine(const std::vector<ProgressColumn<Row>>& columns, const Row& row) {
  std::string line;
  for (size_t i = 0; i < columns.size(); ++i) line += (i ? "," : "") + columns[i].value(row);
  return line;
}

// How many of a learner's columns (`learner_header`) the progress file `file` keeps, given its
// header line: all of them when the headers are equal; fewer when the file was begun by an older
// version whose columns were the first ones of today's (columns are only ever added at the
// end), so that a resumed run keeps the columns it began with. Throws cmbrl::Error naming the
// file and both headers otherwise.
size_t ProgressColumnsKept(const std::filesystem::path& file, const std::string& file_header,
                           const std::string& learner_header);

// The first `count` comma-separated fields of a progress line.
std::string FirstProgressFields(const std::string& line, size_t count);

// A number as progress files write it: shortest round-trip form, "nan" for NaN or infinity.
std::string ProgressNumber(double value);

// A whole table read back. Not thread-safe.
class ProgressTable {
 public:
  // Throws cmbrl::Error naming the file when it cannot be read or a row's field count differs
  // from the header's. Empty lines are skipped. With `max_rows`, only the first rows up to that
  // many are read (those a checkpoint covers); rows after them are not looked at.
  static ProgressTable Read(const std::filesystem::path& path,
                            std::optional<size_t> max_rows = std::nullopt);

  const std::vector<std::string>& header() const { return header_; }
  size_t rows() const { return rows_.size(); }

  // The index of a column; throws cmbrl::Error naming the file, the column and `expected` (what
  // kind of log was expected) when there is none.
  size_t Column(const std::string& name, const std::string& expected) const;
  bool HasColumn(const std::string& name) const;

  // The file's line number of a row (the header is line 1).
  int line(size_t row) const { return line_numbers_.at(row); }

  // A value as a number; throws cmbrl::Error naming the file, the line, the column and the text.
  double Number(size_t row, size_t column) const;

  // A value as written.
  const std::string& Text(size_t row, size_t column) const { return rows_.at(row).at(column); }

  // A value that lists numbers separated by spaces (a report's per-seed columns; "" lists
  // none); throws cmbrl::Error naming the file, the line, the column and the text.
  std::vector<double> Numbers(size_t row, size_t column) const;

 private:
  std::filesystem::path path_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> line_numbers_;
};

}  // namespace cmbrl

// The report's tables from cells alone (no runs): the verdict per task and every cell with its
// seeds, against the original's.
#include "cmbrl/report/table_markdown.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace cmbrl {
namespace {

using ::testing::HasSubstr;

// A cell of three seeds, its mean theirs, beside the original's seeds.
TableCell Cell(const std::string& task, const std::string& planner, std::vector<double> seeds,
               std::vector<double> original, std::vector<double> returns = {1, 1, 1}) {
  TableCell cell;
  cell.task = task;
  cell.planner = planner;
  cell.per_seed = seeds;
  double sum = 0.0;
  for (double v : seeds) sum += v;
  cell.mean = sum / static_cast<double>(seeds.size());
  cell.final_returns = returns;
  cell.return_mean = 1.0;
  cell.original_per_seed = original;
  cell.original_final_returns = {0.5, 2.0, 1.5};
  cell.fewest_steps = 3000;
  return cell;
}

TEST(TableMarkdownTest, TheVerdictSaysWhetherRceViolatesLeastWithItsIntervals) {
  const std::vector<TableCell> cells = {
      Cell("PointGoal1", "rce", {1, 2, 3}, {12, 16, 4}),
      Cell("PointGoal1", "cem", {50, 60, 70}, {106, 65, 77}),
      Cell("PointGoal2", "rce", {100, 200, 300}, {113, 78, 108}),
      Cell("PointGoal2", "cem", {150, 250, 350}, {369, 240, 201}),
      Cell("CarGoal1", "rce", {40, 50, 60}, {2, 1, 3}),
      Cell("CarGoal1", "cem", {10, 20, 30}, {45, 31, 26}),
  };
  const std::string text = ProtocolVerdictMarkdown(cells, 3000);
  EXPECT_THAT(text, HasSubstr("| PointGoal1 | 2.0 ["));
  EXPECT_THAT(text, HasSubstr("| yes | below / inside | below / inside |"));
  EXPECT_THAT(text, HasSubstr("| mean only | above / inside | inside / inside |"));
  EXPECT_THAT(text, HasSubstr("| no | above / inside | below / inside |"));
  const std::string all = ProtocolCellsMarkdown(cells, 3000);
  EXPECT_THAT(all, HasSubstr("| PointGoal1 | MPC-RCE | 3 | 1, 2, 3 | 2.0 ["));
  EXPECT_THAT(all, HasSubstr("| 12, 16, 4 (10.7) | below |"));
  EXPECT_EQ(AgainstRange(5, {}), "");
  EXPECT_EQ(AgainstRange(5, {5, 6}), "inside");
}

}  // namespace
}  // namespace cmbrl

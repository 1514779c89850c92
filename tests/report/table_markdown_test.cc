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

// Table I names what its cells count in: agent steps and episodes for MPC runs, environment
// steps and epochs for model-free ones (whose logs are per epoch).
TEST(TableMarkdownTest, TableOneCountsInTheCellsOwnUnits) {
  const TableCell mpc = Cell("PointGoal2", "rce", {1, 2, 3}, {});
  const std::string episodes = TableMarkdown({mpc}, 3000);
  EXPECT_THAT(episodes, HasSubstr("Violations during the first 3000 agent steps:"));
  EXPECT_THAT(episodes, HasSubstr("the mean EpRet of each run's last 10 episodes in it"));
  TableCell model_free = Cell("PointGoal2", "cpo", {90000}, {});
  model_free.epoch_log = true;
  const std::string epochs = TableMarkdown({model_free}, 3000000);
  EXPECT_THAT(epochs, HasSubstr("Violations during the first 3000000 environment steps:"));
  EXPECT_THAT(epochs, HasSubstr("the mean AverageEpRet of each run's last 10 epochs in it"));
  EXPECT_THAT(epochs, ::testing::Not(HasSubstr("agent steps")));
  // The paper's Table I has no model-free numbers, so no brackets are promised for them.
  EXPECT_THAT(epochs, ::testing::Not(HasSubstr("in brackets")));
  TableCell with_paper = mpc;
  with_paper.paper = 20.0;
  const std::string bracketed = TableMarkdown({with_paper}, 3000);
  EXPECT_THAT(bracketed, HasSubstr("the paper's Table I (mean of 3 seeds over 10,000 steps) in "
                                   "brackets"));
  EXPECT_THAT(bracketed, HasSubstr("(3) [20] |"));
}

TEST(TableMarkdownTest, RunCountIsSingularForOne) {
  EXPECT_EQ(RunCount(0), "0 runs");
  EXPECT_EQ(RunCount(1), "1 run");
  EXPECT_EQ(RunCount(60), "60 runs");
}

// What the runs cost: minutes per seed with their median and the longest per cell, and the
// core-hours of every run; a cell without times (an earlier table's) has no row.
TEST(TableMarkdownTest, ComputeGivesEachRunsMinutesAndTheCoreHours) {
  TableCell rce = Cell("PointGoal2", "rce", {1, 2, 3}, {});
  rce.seeds = {0, 1, 2};
  rce.run_minutes = {21.0, 30.4, 25.0};
  TableCell cem = Cell("PointGoal2", "cem", {1, 2}, {});
  cem.seeds = {3, 4};
  cem.run_minutes = {40.0, 33.6};
  const TableCell untimed = Cell("CarGoal1", "rce", {1, 2, 3}, {});
  const std::string markdown = ComputeMarkdown({rce, cem, untimed});
  // 21 + 30.4 + 25 + 40 + 33.6 = 150 minutes.
  EXPECT_THAT(markdown, HasSubstr("5 runs took 2.5 core-hours; the longest, PointGoal2 MPC-CEM, "
                                  "seed 3, 40 minutes."));
  EXPECT_THAT(markdown, HasSubstr("| PointGoal2 | MPC-RCE | 0, 1, 2 | 21, 30, 25 | 25 | 30 |\n"));
  EXPECT_THAT(markdown, HasSubstr("| PointGoal2 | MPC-CEM | 3, 4 | 40, 34 | 37 | 40 |\n"));
  EXPECT_THAT(markdown, ::testing::Not(HasSubstr("CarGoal1")));
  EXPECT_EQ(ComputeMarkdown({untimed}), "");
  rce.run_minutes = {30.0, 30.0, 30.0};
  EXPECT_THAT(ComputeMarkdown({rce}), HasSubstr("3 runs took 1.5 core-hours"));
  TableCell one = Cell("CarGoal1", "cpo", {7}, {});
  one.seeds = {0};
  one.run_minutes = {491.0};
  EXPECT_THAT(ComputeMarkdown({one}), HasSubstr("1 run took 8.2 core-hours; the longest, "
                                                "CarGoal1 CPO, seed 0, 491 minutes."));
  EXPECT_THAT(ComputeMarkdown({one}), HasSubstr("not counted), one core a run. 1 run"));
  // A run on two cores counts twice its minutes; the table gives its wall minutes.
  one.run_core_minutes = {982.0};
  const std::string two_cores = ComputeMarkdown({one});
  EXPECT_THAT(two_cores, HasSubstr("not counted), each session's time at the cores it ran on "
                                   "(sessions.jsonl's OpenBLAS or LibTorch threads"));
  EXPECT_THAT(two_cores, HasSubstr("1 run took 16.4 core-hours; the longest, CarGoal1 CPO, seed "
                                   "0, 491 minutes."));
  EXPECT_THAT(two_cores, HasSubstr("| CarGoal1 | CPO | 0 | 491 | 491 | 491 |"));
  EXPECT_THAT(two_cores, ::testing::Not(HasSubstr("CPU")));
  // Runs that logged CpuTime: their CPU minutes beside, and their share of the core-hours; a cell
  // whose runs did not log it has "-" there, and its core-hours are not in the share.
  one.run_cpu_minutes = {736.8};
  const std::string with_cpu = ComputeMarkdown({one, rce});
  EXPECT_THAT(with_cpu, HasSubstr("| task | method | seeds | minutes per seed | median | longest "
                                  "| CPU minutes per seed |\n|---|---|---|---|---|---|---|\n"));
  EXPECT_THAT(with_cpu, HasSubstr("| CarGoal1 | CPO | 0 | 491 | 491 | 491 | 737 |\n"));
  EXPECT_THAT(with_cpu, HasSubstr("| PointGoal2 | MPC-RCE | 0, 1, 2 | 30, 30, 30 | 30 | 30 | - |"));
  EXPECT_THAT(with_cpu, HasSubstr("1 run used 12.3 CPU-hours, 75% of its core-hours; the rest is "
                                  "time its cores"));
  EXPECT_THAT(ComputeMarkdown({one}), HasSubstr("the run used 12.3 CPU-hours, 75% of its"));
  rce.run_cpu_minutes = {15.0, 15.0, 30.0};
  EXPECT_THAT(ComputeMarkdown({one, rce}),
              HasSubstr("the runs used 13.3 CPU-hours, 74% of their core-hours; the rest is time "
                        "their cores"));
}

// A declared rule turns "Settings compared" into a decision per pair of settings, over all the
// pairs of every cell; without one there is no decision table.
TEST(TableMarkdownTest, ADeclaredRuleDecidesEachPairOfSettings) {
  const auto arm = [](const std::string& task, const std::string& setting,
                      std::vector<double> violations, std::vector<double> returns) {
    TableCell cell = Cell(task, "rce", violations, {}, returns);
    cell.setting = setting;
    cell.seeds = {0, 1, 2};
    return cell;
  };
  // Violations: differences +1, -1, 0 and 0, +1, -1 against a first arm of mean 100: within +-20.
  // Returns: +2 on every pair against a first arm of mean 10: the interval excludes 0.
  const std::vector<TableCell> cells = {
      arm("PointGoal1", "precision=fp32", {100, 100, 100}, {10, 10, 10}),
      arm("PointGoal1", "precision=bf16", {101, 99, 100}, {12, 12, 12}),
      arm("PointGoal2", "precision=fp32", {100, 100, 100}, {10, 10, 10}),
      arm("PointGoal2", "precision=bf16", {100, 101, 99}, {12, 12, 12}),
  };
  const DecisionRule equivalence{DecisionRule::Kind::kEquivalence, 0.2};
  const std::string decided = SettingComparisonMarkdown(cells, equivalence);
  EXPECT_THAT(decided, HasSubstr("**Decision**, by the rule `experiment.yaml` declares "
                                 "(equivalence: the 90% interval of the mean paired difference "
                                 "holds 0 and lies within +-20% of the first setting's mean)"));
  EXPECT_THAT(decided, HasSubstr("| precision=bf16 | precision=fp32 | 6 in 2 cells | "
                                 "indistinguishable (within +-20.00) | differs (the interval "
                                 "excludes 0) | differs |\n"));
  const DecisionRule difference{DecisionRule::Kind::kDifference, 0.2};
  EXPECT_THAT(SettingComparisonMarkdown({cells[0], cells[1]}, difference),
              HasSubstr("| precision=bf16 | precision=fp32 | 3 in 1 cell | no difference shown | "
                        "higher | violations no difference shown, return higher |\n"));
  EXPECT_THAT(SettingComparisonMarkdown(cells), ::testing::Not(HasSubstr("**Decision**")));
}

}  // namespace
}  // namespace cmbrl

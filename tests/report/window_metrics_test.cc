#include "cmbrl/report/window_metrics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/report/table_markdown.h"
#include "tests/error_message.h"
#include "tests/report/report_fixture.h"

namespace cmbrl {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(ReportEpisodesTest, HeavyEpisodesAndFeasibleFractionCountOnlyTheWindow) {
  RunRecord run;
  const auto episode = [](std::int64_t end, double cost, double feasible) {
    EpisodePoint point;
    point.end_step = end;
    point.steps = 100;
    point.episode_cost = cost;
    point.feasible_fraction = feasible;
    return point;
  };
  run.episodes = {episode(100, 25, 0.2), episode(200, 19, 0.6), episode(300, 20, 0.4),
                  episode(400, 40, 0.0)};
  EXPECT_EQ(HeavyEpisodesWithin(run, 300), 2);  // 25 and 20; 19 is not, 40 ends at 400
  EXPECT_NEAR(FeasibleFractionWithin(run, 300), 0.4, 1e-12);
  EXPECT_TRUE(std::isnan(FeasibleFractionWithin(run, 50)));
}

// A model-free epoch in which no episode ended (NaN return, as the last, partial epoch of a
// budget that is not a whole number of epochs) does not take a place among the last ones.
TEST(ReportEpisodesTest, TheFinalReturnSkipsEpochsWithNoEpisode) {
  RunRecord run;
  const auto epoch = [](std::int64_t end, double ret) {
    EpisodePoint point;
    point.end_step = end;
    point.steps = 100;
    point.episode_return = ret;
    return point;
  };
  const double none = std::nan("");
  run.episodes = {epoch(100, 1.0), epoch(200, 2.0), epoch(300, none), epoch(400, 4.0),
                  epoch(500, none)};
  EXPECT_NEAR(FinalReturn(run, 500, 2), 3.0, 1e-12);  // 2 and 4, not the NaN after them
  EXPECT_NEAR(FinalReturn(run, 500, 3), 7.0 / 3.0, 1e-12);
  EXPECT_NEAR(FinalReturn(run, 350, 1), 2.0, 1e-12);
  run.episodes = {epoch(100, none)};
  EXPECT_TRUE(std::isnan(FinalReturn(run, 500)));
}

// The first epoch: the episodes before a run's first refit, ours against the original's.
TEST(ReportTableTest, TheFirstEpochComparesOursWithTheOriginalsOnEqualData) {
  const auto run = [](std::uint64_t seed, const std::vector<double>& costs, int per_epoch) {
    RunRecord record;
    record.config.task = "CarGoal1";
    record.config.planner = "random";
    record.config.seed = seed;
    record.config.training.episodes_per_epoch = per_epoch;
    for (size_t i = 0; i < costs.size(); ++i) {
      EpisodePoint point;
      point.steps = 75;
      point.end_step = 75 * static_cast<std::int64_t>(i + 1);
      point.episode_cost = costs[i];
      point.episode_return = 10.0 + static_cast<double>(i);
      record.episodes.push_back(point);
    }
    return record;
  };
  const std::vector<RunRecord> ours = {run(0, {3, 4, 5}, 2), run(1, {1, 0, 9}, 2)};
  // The original's seed 10 has not finished its first epoch of 3 episodes: left out.
  const std::vector<RunRecord> original = {run(0, {0, 1, 2}, 3), run(10, {2}, 3)};
  const std::optional<FirstEpoch> first = FirstEpochOf(ours[0]);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->episodes, 2);
  EXPECT_EQ(first->violations, 7.0);
  EXPECT_EQ(first->mean_return, 10.5);
  EXPECT_FALSE(FirstEpochOf(original[1]).has_value());
  RunRecord model_free = ours[0];
  model_free.epoch_log = true;
  EXPECT_FALSE(FirstEpochOf(model_free).has_value());

  const std::vector<TableCell> cells = ViolationTable(ours, 150, original);
  ASSERT_EQ(cells.size(), 1u);
  ASSERT_EQ(cells[0].first_epochs.size(), 2u);
  ASSERT_EQ(cells[0].original_first_epochs.size(), 1u);
  EXPECT_EQ(cells[0].original_first_epochs[0].violations, 3.0);
  EXPECT_THAT(TableMarkdown(cells, 150),
              HasSubstr("| CarGoal1 | MPC-random | 2 | 4.0 (7, 1) | 3.0 (3) | 10.5 (10.5, 10.5) "
                        "| 11.0 (11.0) |"));
  EXPECT_THAT(TableCsv(cells, 150), HasSubstr(",7 1,10.5 10.5,3,11,,,\n"));
  // Without the original's first epochs there is no such table.
  EXPECT_THAT(TableMarkdown(ViolationTable(ours, 150), 150), Not(HasSubstr("The first epoch")));
}

// HazardSteps and VaseSteps: summed over the window per seed, shown for a cell only when every
// seed logged them (runs of older versions and the original's logs did not).
TEST(ReportTableTest, WhereTheViolationsHappenedIsSummedOverTheWindow) {
  const auto run = [](const std::string& planner, std::uint64_t seed,
                      const std::vector<std::array<double, 3>>& episodes) {
    RunRecord record;
    record.config.task = "CarGoal2";
    record.config.planner = planner;
    record.config.seed = seed;
    for (size_t i = 0; i < episodes.size(); ++i) {
      EpisodePoint point;
      point.steps = 100;
      point.end_step = 100 * static_cast<std::int64_t>(i + 1);
      point.episode_cost = episodes[i][0];
      point.hazard_steps = episodes[i][1];
      point.vase_steps = episodes[i][2];
      record.episodes.push_back(point);
    }
    return record;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<RunRecord> runs = {
      run("rce", 0, {{3, 2, 1}, {5, 1, 5}, {9, 9, 0}}),  // 300 steps: 8 hazard, 6 vase in 200
      run("rce", 1, {{2, 0, 2}, {0, 0, 0}}), run("cem", 0, {{4, 4, 0}, {1, 1, 0}}),
      run("cem", 1, {{6, nan, nan}, {1, nan, nan}}),  // an older version's log
  };
  const std::optional<ViolationCauses> causes = ViolationCausesWithin(runs[0], 200);
  ASSERT_TRUE(causes.has_value());
  EXPECT_EQ(causes->hazard_steps, 3);
  EXPECT_EQ(causes->vase_steps, 6);
  EXPECT_FALSE(ViolationCausesWithin(runs[3], 200).has_value());
  RunRecord epochs = runs[0];
  epochs.epoch_log = true;
  EXPECT_FALSE(ViolationCausesWithin(epochs, 200).has_value());

  const std::vector<TableCell> cells = ViolationTable(runs, 200);
  ASSERT_EQ(cells.size(), 2u);
  ASSERT_EQ(cells[0].planner, "rce");
  EXPECT_EQ(cells[0].hazard_steps, (std::vector<int>{3, 0}));
  EXPECT_EQ(cells[0].vase_steps, (std::vector<int>{6, 2}));
  EXPECT_TRUE(cells[1].hazard_steps.empty());  // one seed did not log them
  EXPECT_TRUE(cells[1].vase_steps.empty());
  const std::string markdown = TableMarkdown(cells, 200);
  EXPECT_THAT(markdown, HasSubstr("Where the violations happened"));
  EXPECT_THAT(markdown, HasSubstr("| CarGoal2 | MPC-RCE | 8, 2 | 3, 0 | 6, 2 |"));
  EXPECT_THAT(markdown, Not(HasSubstr("| CarGoal2 | MPC-CEM | 5, 7 |")));
  const std::string csv = TableCsv(cells, 200);
  EXPECT_THAT(csv, HasSubstr("hazard_steps_per_seed,vase_steps_per_seed,source\n"));
  EXPECT_THAT(csv, HasSubstr(",3 0,6 2,\n"));
  // Without any cell that logged them there is no such section.
  runs.erase(runs.begin(), runs.begin() + 2);
  EXPECT_THAT(TableMarkdown(ViolationTable(runs, 200), 200),
              Not(HasSubstr("Where the violations happened")));
}

}  // namespace
}  // namespace cmbrl

// Reading runs: progress logs of both learner families, sweeps and a report's kept logs, and
// what is refused (bad values, rows past the checkpoint, a copied run).
#include "cmbrl/report/run_logs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "cmbrl/report/table.h"
#include "tests/error_message.h"
#include "tests/report/report_fixture.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ReportTest;

// Every algorithm's family has a reader of its progress.csv, and the two families read
// differently (a row per episode, a row per epoch).
TEST(ReportEpisodesTest, EveryLearnerFamilyHasItsEpisodeReader) {
  for (const AlgorithmEntry& entry : Algorithms()) {
    SCOPED_TRACE(entry.name);
    EXPECT_NE(EpisodeReaderOf(entry.family->log), nullptr);
  }
  EXPECT_EQ(EpisodeReaderOf(MpcFamily().log), &ReadProgressEpisodes);
  EXPECT_EQ(EpisodeReaderOf(PolicyOptFamily().log), &ReadEpochLog);
}

TEST_F(ReportTest, AReportsLogsMakeItAgainWithoutTheRuns) {
  const fs::path out = sweep_ / "report";
  const std::vector<RunRecord> runs = ReadSweep(sweep_.string());
  KeepRunLogs(runs, out.string());
  // The logs alone (no checkpoints) give the same runs and the same table.
  const std::vector<RunRecord> again = ReadSweep(out.string());
  ASSERT_EQ(again.size(), runs.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(again[i].name, runs[i].name);
    EXPECT_EQ(again[i].source, out / "run-logs" / runs[i].name);
    EXPECT_EQ(again[i].episodes.size(), runs[i].episodes.size());
  }
  EXPECT_EQ(TableCsv(ViolationTable(again, 300), 300), TableCsv(ViolationTable(runs, 300), 300));

  // A report's logs beside the sweep they came from: each run once, read from the sweep.
  const std::vector<RunRecord> both = ReadSweeps({out.string(), sweep_.string()});
  ASSERT_EQ(both.size(), runs.size());
  for (const RunRecord& run : both) EXPECT_EQ(run.source.parent_path(), sweep_ / "runs");

  // A log that is not the first rows of the run of its name is another run: refused by name.
  const fs::path log = out / "run-logs" / "PointGoal1-cem-s0" / "progress.csv";
  std::ofstream(log, std::ios::app) << "9,9,1,1,500,0,0,0,0,0,0,0,100,0,0,0,0\n";
  EXPECT_THAT(testing::ErrorMessage([&] {
                ReadSweeps({sweep_.string(), out.string()});
              }),
              HasSubstr("run 'PointGoal1-cem-s0' is in both"));

  // A later report replaces the logs whole: only its own runs are left.
  KeepRunLogs({runs.front()}, out.string());
  ASSERT_EQ(ReadSweep(out.string()).size(), 1u);
  EXPECT_FALSE(fs::exists(out / "run-logs.new"));

  // Anything but logs under run-logs/ is not the report's to replace.
  std::ofstream(out / "run-logs" / runs.front().name / "notes.txt") << "mine";
  EXPECT_THAT(testing::ErrorMessage([&] { KeepRunLogs(runs, out.string()); }),
              HasSubstr("notes.txt': expected only run logs"));
  EXPECT_TRUE(fs::exists(out / "run-logs" / runs.front().name / "notes.txt"));

  // A folder with neither runs/ nor run-logs/ is named.
  EXPECT_THAT(testing::ErrorMessage([&] { ReadSweep((sweep_ / "none").string()); }),
              HasSubstr("holds neither runs/ nor run-logs/"));
}

TEST_F(ReportTest, RunsShortOfTheWindowAreLeftOutByName) {
  std::vector<RunRecord> runs = ReadSweep(sweep_.string());
  // The CarGoal2 runs reached 450 steps but for cem seed 1 (0), PointGoal1 cem seed 1 300, the
  // others 400.
  const std::vector<std::string> left_out = LeaveOutRunsShortOf(runs, 400);
  EXPECT_THAT(left_out,
              ::testing::ElementsAre("CarGoal2-cem-s1 (0 steps)", "PointGoal1-cem-s1 (300 steps)"));
  ASSERT_EQ(runs.size(), 5u);
  for (const RunRecord& run : runs) EXPECT_GE(StepsReached(run), 400);
}

// A report reads what the run's checkpoint covers: a row added after it (by hand, or by a run
// still going) is not counted.
TEST_F(ReportTest, RowsTheCheckpointDoesNotCoverAreNotCounted) {
  const fs::path progress = sweep_ / "runs" / "PointGoal1-rce-s0" / "progress.csv";
  ProgressRow row;
  row.epoch = 1;
  row.episode = 5;
  row.episode_cost = 99;
  row.steps = 100;
  row.total_env_interacts = 500;
  std::ofstream(progress, std::ios::app) << ProgressCsvLine(row) << "\n";
  const std::vector<RunRecord> runs = ReadSweep(sweep_.string());
  const auto run = std::find_if(runs.begin(), runs.end(),
                                [](const RunRecord& r) { return r.name == "PointGoal1-rce-s0"; });
  ASSERT_NE(run, runs.end());
  ASSERT_EQ(run->episodes.size(), 4u);
  EXPECT_DOUBLE_EQ(run->episodes.back().cumulative_violations, 12.0);  // 1 + 0 + 2 + 9
}

// A run folder copied (or moved and copied back) keeps its run id: a report counts it once and
// refuses the second, naming both folders.
TEST_F(ReportTest, ACopiedRunIsRefusedNamingBothFolders) {
  const fs::path runs = sweep_ / "runs";
  RecordRunSession(RunDirectory(runs / "PointGoal1-rce-s0"), 0, NumericsSetup{});  // run ids
  RecordRunSession(RunDirectory(runs / "PointGoal1-rce-s1"), 0, NumericsSetup{});
  fs::copy(runs / "PointGoal1-rce-s1", runs / "PointGoal1-rce-s7", fs::copy_options::recursive);
  const std::string message = testing::ErrorMessage([&] { ReadSweep(sweep_.string()); });
  EXPECT_THAT(message, HasSubstr("PointGoal1-rce-s1' and '"));
  EXPECT_THAT(message, HasSubstr("PointGoal1-rce-s7' hold one run (run id "));
  // Distinct runs have distinct ids.
  fs::remove_all(runs / "PointGoal1-rce-s7");
  std::set<std::string> ids;
  for (const RunRecord& run : ReadSweep(sweep_.string())) {
    if (!run.sessions.empty()) ids.insert(RunIdOf(run.sessions));
  }
  EXPECT_EQ(ids.size(), 2u);
  EXPECT_EQ(ids.begin()->size(), 32u);
}

// A run's core-seconds: each session's share of its time at the cores that session records; a
// run without sessions counts one core.
TEST(ReportComputeTest, EachSessionsTimeCountsAtItsCores) {
  RunRecord run;
  for (int i = 1; i <= 4; ++i) {
    EpisodePoint point;
    point.end_step = 100 * i;
    point.elapsed_seconds = 60.0 * i;
    run.episodes.push_back(point);
  }
  EXPECT_DOUBLE_EQ(CoreSecondsTaken(run), 240.0);
  const auto session = [](std::int64_t steps_done, int blas_threads, int torch_threads) {
    RunSession s;
    s.steps_done = steps_done;
    s.setup.blas_threads = blas_threads;
    s.setup.torch_threads = torch_threads;
    return s;
  };
  // Steps 0-200 on one core (120 s), 200-400 on two (120 s).
  run.sessions = {session(0, 1, 1), session(200, 2, 1)};
  EXPECT_DOUBLE_EQ(CoreSecondsTaken(run), 120.0 + 2 * 120.0);
  // A session cut before its first point leaves nothing to the one it began at the same step;
  // a session of a version that recorded no threads counts one core; LibTorch's threads count.
  run.sessions = {session(0, 0, 0), session(0, 2, 1), session(300, 1, 4)};
  EXPECT_DOUBLE_EQ(CoreSecondsTaken(run), 2 * 180.0 + 4 * 60.0);
  EXPECT_EQ(SessionCores(RunSession().setup), 1);
  run.episodes.clear();
  EXPECT_TRUE(std::isnan(CoreSecondsTaken(run)));
}

// Runs named by hand fall in one cell by their names (task and method, no setting): made with
// different configs, they are told apart by the keys they differ in and never pooled; where
// that still leaves two configs, or two runs of one seed, in a cell, the report refuses.
TEST_F(ReportTest, ACellPoolsTheSeedsOfOneConfig) {
  const fs::path mine = sweep_ / "mine";
  // A run of PointGoal2 RCE in mine/runs/<name> (named by hand, or as a sweep names a setting).
  const auto write = [&](const std::string& name, std::uint64_t seed,
                         const std::function<void(TrainConfig&)>& adjust) {
    testing::WriteRun(mine, "PointGoal2", "rce", seed, 100, {1, 2, 3}, 0, "", adjust);
    fs::rename(mine / "runs" / fmt::format("PointGoal2-rce-s{}", seed), mine / "runs" / name);
  };
  const auto at = [](int population, double gamma) {
    return [population, gamma](TrainConfig& config) {
      config.planning.cross_entropy.population = population;
      config.objective.gamma = gamma;
    };
  };
  const auto settings = [](const std::vector<RunRecord>& runs) {
    std::vector<std::string> found;
    for (const RunRecord& run : runs) found.push_back(run.name + ": " + SettingOf(run));
    return found;
  };
  write("mine-a", 0, at(100, 0.99));
  write("mine-b", 1, at(500, 0.99));
  write("mine-c", 2, at(100, 0.99));
  // Before, one cell "PointGoal2" of three seeds with two configs mixed.
  EXPECT_THAT(settings(ReadSweep(mine.string())),
              ::testing::ElementsAre("mine-a: population=100", "mine-b: population=500",
                                     "mine-c: population=100"));
  const std::vector<TableCell> cells = ViolationTable(ReadSweep(mine.string()), 300);
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_EQ(WithSetting(cells[0].task, cells[0].setting), "PointGoal2 (population=100)");
  EXPECT_EQ(cells[0].seeds, (std::vector<std::uint64_t>{0, 2}));
  EXPECT_EQ(WithSetting(cells[1].task, cells[1].setting), "PointGoal2 (population=500)");

  // A sweep's runs of one setting agree: nothing is added to their names' settings, and a key
  // their names give (an axis) is not repeated where they meet runs named by hand.
  for (const RunRecord& run : ReadSweep(sweep_.string())) EXPECT_EQ(run.config_setting, "");
  testing::WriteRun(sweep_, "PointGoal2", "rce", 3, 100, {1, 1, 1}, 0, "population=500",
                    at(500, 0.98));
  testing::WriteRun(sweep_, "PointGoal2", "rce", 4, 100, {1, 1, 1}, 0, "population=500",
                    at(500, 0.99));
  EXPECT_THAT(
      settings(ReadSweeps({sweep_.string(), mine.string()})),
      ::testing::IsSupersetOf({"pointgoal2-rce-population=500-s3: population=500-gamma=0.98",
                               "pointgoal2-rce-population=500-s4: population=500-gamma=0.99",
                               "mine-b: population=500"}));

  // Keys several runs differ in, each run's values of all of them; the budget is none of them.
  write("mine-d", 4, at(100, 0.9));
  write("mine-f", 5, [&](TrainConfig& config) {
    at(100, 0.99)(config);
    config.training.total_steps = 5000;
  });
  EXPECT_THAT(settings(ReadSweep(mine.string())),
              ::testing::ElementsAre(
                  "mine-a: population=100-gamma=0.99", "mine-b: population=500-gamma=0.99",
                  "mine-c: population=100-gamma=0.99", "mine-d: population=100-gamma=0.9",
                  "mine-f: population=100-gamma=0.99"));

  // Two runs of one seed in one cell: refused, naming both.
  write("mine-e", 2, at(100, 0.99));
  const std::string seed_twice =
      testing::ErrorMessage([&] { ViolationTable(ReadSweep(mine.string()), 300); });
  EXPECT_THAT(seed_twice, HasSubstr("mine-c' and '"));
  EXPECT_THAT(seed_twice, HasSubstr("mine-e' are both seed 2 of one cell (PointGoal2 "
                                    "(population=100-gamma=0.99), MPC-RCE)"));
  fs::remove_all(mine / "runs" / "mine-e");

  // A run whose name gives a setting that runs of another config reach too: refused, naming the
  // key.
  testing::WriteRun(mine, "PointGoal2", "rce", 6, 100, {1, 1, 1}, 0, "population=100-gamma=0.99",
                    [&](TrainConfig& config) {
                      at(100, 0.99)(config);
                      config.planning.cross_entropy.max_iterations = 3;
                    });
  const std::string two_configs = testing::ErrorMessage([&] { ReadSweep(mine.string()); });
  EXPECT_THAT(two_configs, HasSubstr("fall in one cell (PointGoal2 rce population=100-gamma=0.99)"
                                     " but were made with different configs ('planning."
                                     "max_iterations' is 8 in the first, 3 in the second)"));
}

// Two experiments reported together: one's cells named by an axis, the other's by nothing. A
// plain cell of another config than the preset's says how it differs (as the axis cells do),
// instead of reading as the preset's; a plain cell that differs only in what the axis names
// stays plain, and so does a cell a word given by hand tells apart.
TEST_F(ReportTest, CellsOfOneTaskAndMethodSayWhatSetsThemApart) {
  const fs::path axis = sweep_ / "axis";
  const fs::path other = sweep_ / "other";
  const auto at = [](int population, double gamma) {
    return [population, gamma](TrainConfig& config) {
      config.planning.cross_entropy.population = population;
      config.objective.gamma = gamma;
    };
  };
  const auto cells = [](const std::vector<std::string>& folders) {
    std::vector<std::string> found;
    for (const TableCell& cell : ViolationTable(ReadSweeps(folders), 300)) {
      found.push_back(WithSetting(cell.task, cell.setting));
    }
    return found;
  };
  for (std::uint64_t seed : {0, 1}) {
    testing::WriteRun(axis, "PointGoal2", "rce", seed, 100, {1, 2, 3}, 0, "population=100",
                      at(100, 0.99));
    testing::WriteRun(axis, "PointGoal2", "rce", seed, 100, {1, 2, 3}, 0, "population=500",
                      at(500, 0.99));
  }
  // The preset beside the axis: the plain cell is the other value of the axis.
  testing::WriteRun(other, "PointGoal2", "rce", 0, 100, {1, 2, 3}, 0, "", at(300, 0.99));
  EXPECT_THAT(cells({axis.string(), other.string()}),
              ::testing::ElementsAre("PointGoal2", "PointGoal2 (population=100)",
                                     "PointGoal2 (population=500)"));
  // Another config: every cell gives its value of the key no label names.
  fs::remove_all(other);
  for (std::uint64_t seed : {0, 1}) {
    testing::WriteRun(other, "PointGoal2", "rce", seed, 100, {1, 2, 3}, 0, "", at(100, 0.9));
  }
  EXPECT_THAT(
      cells({axis.string(), other.string()}),
      ::testing::ElementsAre("PointGoal2 (gamma=0.9)", "PointGoal2 (population=100-gamma=0.99)",
                             "PointGoal2 (population=500-gamma=0.99)"));
  // A cell named by hand ("policy") is told apart by its name's word: nothing is added.
  testing::WriteRun(axis, "PointGoal2", "rce", 0, 100, {1, 2, 3}, 0, "policy", at(100, 0.5));
  EXPECT_THAT(cells({axis.string(), other.string()}),
              ::testing::ElementsAre("PointGoal2 (gamma=0.9)", "PointGoal2 (policy)",
                                     "PointGoal2 (population=100-gamma=0.99)",
                                     "PointGoal2 (population=500-gamma=0.99)"));
  fs::remove_all(axis / "runs" / SweepRunName("PointGoal2", "rce", "policy", 0));
  // Each experiment alone says no more than its names.
  EXPECT_THAT(cells({other.string()}), ::testing::ElementsAre("PointGoal2"));
  EXPECT_THAT(cells({axis.string()}),
              ::testing::ElementsAre("PointGoal2 (population=100)", "PointGoal2 (population=500)"));
  // Another task's and another method's cells are compared with nothing here.
  testing::WriteRun(other, "PointGoal2", "cem", 0, 100, {1, 2, 3}, 0, "", at(100, 0.5));
  testing::WriteRun(other, "PointGoal1", "rce", 0, 100, {1, 2, 3}, 0, "", at(100, 0.5));
  const std::vector<std::string> all = cells({axis.string(), other.string()});
  EXPECT_EQ(std::count(all.begin(), all.end(), "PointGoal1"), 1);
  EXPECT_EQ(std::count(all.begin(), all.end(), "PointGoal2"), 1);  // the CEM cell
}

// Values outside their domain are refused naming the file, the line and the column, whatever
// the manifest says of them.
TEST_F(ReportTest, ValuesOutsideTheirDomainAreNamed) {
  const fs::path progress = sweep_ / "bad-progress.csv";
  const auto write_row = [&](double cost, double episode_return, int steps) {
    ProgressRow row;
    row.epoch = 1;
    row.episode = 1;
    row.episode_cost = cost;
    row.episode_return = episode_return;
    row.steps = steps;
    row.total_env_interacts = 100;
    std::ofstream(progress, std::ios::trunc) << ProgressCsvHeader() << "\n"
                                             << ProgressCsvLine(row) << "\n";
  };
  const auto row_with = [&](double cost, double episode_return, int steps) {
    write_row(cost, episode_return, steps);
    return testing::ErrorMessage([&] { ReadProgressEpisodes(progress.string()); });
  };
  const std::string count = "expected a whole count from 0 to the episode's steps";
  EXPECT_THAT(row_with(std::nan(""), 0, 100), HasSubstr("line 2: EpCost is nan: " + count));
  EXPECT_THAT(row_with(-7, 0, 100), HasSubstr("line 2: EpCost is -7: " + count));
  EXPECT_THAT(row_with(1e300, 0, 100), HasSubstr("line 2: EpCost is 1e+300: " + count));
  EXPECT_THAT(row_with(101, 0, 100), HasSubstr("line 2: EpCost is 101: " + count));
  EXPECT_THAT(row_with(2.5, 0, 100), HasSubstr("line 2: EpCost is 2.5: expected a whole count"));
  EXPECT_THAT(row_with(1, std::nan(""), 100),
              HasSubstr("line 2: EpRet is nan: expected a finite return"));
  EXPECT_THAT(row_with(1, 0, 150), HasSubstr("line 2: Steps is 150: expected the episode's "
                                             "steps, at most the rise of TotalEnvInteracts"));
  write_row(100, -3.5, 100);  // the edges are in the domain
  EXPECT_NO_THROW(ReadProgressEpisodes(progress.string()));

  const fs::path epochs = sweep_ / "bad-epochs.csv";
  std::ofstream(epochs) << "AverageEpRet,AverageEpCost,CumulativeCost,TotalEnvInteracts\n"
                        << "1,2,40,300\n1,2,30,600\n";
  EXPECT_THAT(testing::ErrorMessage([&] { ReadEpochLog(epochs.string()); }),
              HasSubstr("bad-epochs.csv line 3: CumulativeCost is 30: expected a running count "
                        "that rises by at most the epoch's steps"));
  EXPECT_EQ(ReadEpochLog(epochs.string(), 1).size(), 1u);  // the rows a checkpoint covers
  // An epoch in which no episode ended has no means (nan); infinities and negative costs are
  // refused.
  std::ofstream(epochs, std::ios::trunc)
      << "AverageEpRet,AverageEpCost,CumulativeCost,TotalEnvInteracts\n"
      << "nan,nan,0,300\n1,2,2,600\n";
  EXPECT_EQ(ReadEpochLog(epochs.string()).size(), 2u);
  std::ofstream(epochs, std::ios::trunc)
      << "AverageEpRet,AverageEpCost,CumulativeCost,TotalEnvInteracts\n"
      << "inf,1,0,300\n";
  EXPECT_THAT(testing::ErrorMessage([&] { ReadEpochLog(epochs.string()); }),
              HasSubstr("line 2: AverageEpRet is inf: expected a finite mean return"));
  std::ofstream(epochs, std::ios::trunc)
      << "AverageEpRet,AverageEpCost,CumulativeCost,TotalEnvInteracts\n"
      << "1,-3,0,300\n";
  EXPECT_THAT(testing::ErrorMessage([&] { ReadEpochLog(epochs.string()); }),
              HasSubstr("line 2: AverageEpCost is -3: expected a finite mean cost of 0 or more"));
}

// A run's Time column is its wall seconds over all its sessions, CpuTime its CPU seconds: read
// per point, the last one the run's so far; a log without them (older runs) has none, and a bad
// one is named.
TEST_F(ReportTest, TheTimeColumnGivesTheRunsWallSeconds) {
  const fs::path progress = sweep_ / "timed-progress.csv";
  const auto write = [&](std::vector<double> seconds, double cpu_share = 1.5) {
    std::ofstream out(progress, std::ios::trunc);
    out << ProgressCsvHeader() << "\n";
    for (size_t i = 0; i < seconds.size(); ++i) {
      ProgressRow row;
      row.epoch = 1;
      row.episode = static_cast<int>(i) + 1;
      row.steps = 100;
      row.total_env_interacts = 100 * (static_cast<std::int64_t>(i) + 1);
      row.time_seconds = seconds[i];
      row.cpu_seconds = seconds[i] * cpu_share;
      out << ProgressCsvLine(row) << "\n";
    }
  };
  write({12.5, 130.25});
  RunRecord run;
  run.episodes = ReadProgressEpisodes(progress.string());
  ASSERT_EQ(run.episodes.size(), 2u);
  EXPECT_DOUBLE_EQ(run.episodes[0].elapsed_seconds, 12.5);
  EXPECT_DOUBLE_EQ(SecondsTaken(run), 130.25);
  EXPECT_DOUBLE_EQ(run.episodes[0].cpu_seconds, 18.75);
  EXPECT_DOUBLE_EQ(CpuSecondsTaken(run), 195.375);
  EXPECT_TRUE(std::isnan(SecondsTaken(RunRecord{})));
  EXPECT_TRUE(std::isnan(CpuSecondsTaken(RunRecord{})));
  write({-1});
  EXPECT_THAT(testing::ErrorMessage([&] { ReadProgressEpisodes(progress.string()); }),
              HasSubstr("timed-progress.csv line 2: Time is -1.000: expected the run's wall "
                        "seconds so far (0 or more)"));
  write({10}, -0.5);
  EXPECT_THAT(testing::ErrorMessage([&] { ReadProgressEpisodes(progress.string()); }),
              HasSubstr("timed-progress.csv line 2: CpuTime is -5.000: expected the run's CPU "
                        "seconds so far (0 or more)"));
  // A log begun before CpuTime was kept: its header ends at VaseSteps.
  {
    std::ofstream out(progress, std::ios::trunc);
    out << FirstProgressFields(ProgressCsvHeader(), 16) << "\n"
        << "1,1,0,0,100,0,7.5,0,0,0,0,0,100,0,0,0\n";
  }
  run.episodes = ReadProgressEpisodes(progress.string());
  EXPECT_DOUBLE_EQ(SecondsTaken(run), 7.5);
  EXPECT_TRUE(std::isnan(CpuSecondsTaken(run)));

  const fs::path epochs = sweep_ / "timed-epochs.csv";
  std::ofstream(epochs)
      << "AverageEpRet,AverageEpCost,CumulativeCost,TotalEnvInteracts,Time,CpuTime\n"
      << "1,2,40,300,61.5,118.25\n";
  EXPECT_DOUBLE_EQ(ReadEpochLog(epochs.string()).at(0).elapsed_seconds, 61.5);
  EXPECT_DOUBLE_EQ(ReadEpochLog(epochs.string()).at(0).cpu_seconds, 118.25);
  std::ofstream(epochs, std::ios::trunc)
      << "AverageEpRet,AverageEpCost,CumulativeCost,TotalEnvInteracts\n1,2,40,300\n";
  EXPECT_TRUE(std::isnan(ReadEpochLog(epochs.string()).at(0).elapsed_seconds));
  EXPECT_TRUE(std::isnan(ReadEpochLog(epochs.string()).at(0).cpu_seconds));
}

TEST_F(ReportTest, BadProgressIsNamed) {
  const fs::path progress = sweep_ / "runs" / "PointGoal1-rce-s0" / "progress.csv";
  std::ofstream(progress) << ProgressCsvHeader() << "\n1,1,oops,0,100,0,0,0,0,0,0,0,100,0,0,0,0\n";
  EXPECT_THAT(testing::ErrorMessage([&] { ReadProgressEpisodes(progress.string()); }),
              HasSubstr("progress.csv line 2: EpRet is 'oops': expected a number"));
  // In a sweep, the run's checkpoint no longer covers what progress.csv holds: refused by name.
  EXPECT_THAT(testing::ErrorMessage([&] { ReadSweep(sweep_.string()); }),
              HasSubstr("PointGoal1-rce-s0/progress.csv' has 1 rows but the checkpoint covers 4"));
}

}  // namespace
}  // namespace cmbrl

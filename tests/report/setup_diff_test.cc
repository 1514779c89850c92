#include "cmbrl/report/setup_diff.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/error_message.h"
#include "tests/report/report_fixture.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::kConfigs;
using ::testing::Not;
using testing::ReportTest;

// The setup notes are generic over the config's keys: every key that differs from the paper's
// preset of a run's task and method is named, with the cells it differs in, and nothing else.
TEST(ReportTableTest, TheSetupNotesNameEveryKeyThatDiffersWithItsCells) {
  const auto run = [](const std::string& task, const std::string& planner) {
    RunRecord record;
    record.config.task = task;
    record.config.planner = planner;
    record.config.ensemble.ensemble_size = task.rfind("Car", 0) == 0 ? 5 : 4;
    record.config.training.total_steps = 10000;
    record.episodes.push_back(EpisodePoint{});
    return record;
  };
  std::vector<RunRecord> runs = {run("CarGoal2", "rce"), run("CarGoal2", "cem"),
                                 run("PointGoal1", "cem"), run("PointGoal1", "random")};
  const auto about = [](const std::string& text) { return ::testing::Contains(HasSubstr(text)); };
  EXPECT_THAT(SetupDifferences(runs, 3000, kConfigs), Not(about("`")));  // the paper's presets
  runs[0].config.ensemble.predict_delta = true;
  runs[1].config.ensemble.predict_delta = true;
  runs[0].config.classifier.threshold = 0.3;
  runs[2].config.classifier.threshold = 0.3;
  runs[3].config.planning.random.samples = 1000;
  runs[2].config.classifier.min_child_weight = 2.0;  // a key a hand-written list once forgot
  runs[2].config.training.label_every_step = true;
  const std::vector<std::string> notes = SetupDifferences(runs, 3000, kConfigs);
  EXPECT_THAT(notes, ::testing::Contains("`ensemble.predict_delta` is true, the paper's false "
                                         "(CarGoal2 MPC-RCE, CarGoal2 MPC-CEM)."));
  EXPECT_THAT(notes, ::testing::Contains("`classifier.threshold` is 0.3, the paper's 0.5 "
                                         "(CarGoal2 MPC-RCE, PointGoal1 MPC-CEM)."));
  EXPECT_THAT(notes, ::testing::Contains("`planning.random_samples` is 1000, the paper's 5000 "
                                         "(PointGoal1 MPC-random)."));
  EXPECT_THAT(notes, about("`classifier.min_child_weight` is 2, the paper's 0.001"));
  EXPECT_THAT(notes, about("`training.label_every_step` is true, the paper's false"));
  EXPECT_THAT(notes, Not(about("`seed`")));
}

// A key set in one setting of a task and method names that setting's cell, not every cell of
// the task and method: reports of several experiments (or of an axis) put such cells side by
// side, and one label for both would say the key is set in both.
TEST(ReportTableTest, TheSetupNotesNameACellWithItsSetting) {
  const auto run = [](const std::string& name, bool previous_action) {
    RunRecord record;
    record.name = name;
    record.config.task = "CarGoal2";
    record.config.planner = "rce";
    record.config.ensemble.ensemble_size = 5;
    record.config.training.total_steps = 10000;
    record.config.previous_action = previous_action;
    record.episodes.push_back(EpisodePoint{});
    return record;
  };
  const std::vector<RunRecord> runs = {run("cargoal2-rce-s0", true),
                                       run("cargoal2-rce-predict_delta=false-s0", false)};
  EXPECT_THAT(SetupDifferences(runs, 3000, kConfigs),
              ::testing::Contains("`environment.previous_action` is true, the paper's false "
                                  "(CarGoal2 MPC-RCE)."));
  const std::vector<RunRecord> other_way = {run("cargoal2-rce-s0", false),
                                            run("cargoal2-rce-predict_delta=false-s0", true)};
  EXPECT_THAT(SetupDifferences(other_way, 3000, kConfigs),
              ::testing::Contains("`environment.previous_action` is true, the paper's false "
                                  "(CarGoal2 (predict_delta=false) MPC-RCE)."));
}

// The counting window is said in each family's unit: agent steps against the paper's Table I for
// MPC runs, environment steps for model-free ones, which the paper's Table I leaves out.
TEST(ReportTableTest, TheSetupNotesSayTheWindowInEachFamilysUnit) {
  RunRecord mpc;
  mpc.config.task = "PointGoal2";
  mpc.config.planner = "rce";
  mpc.episodes.push_back(EpisodePoint{});
  RunRecord model_free;
  model_free.config.task = "PointGoal2";
  model_free.config.algorithm = "cpo";
  model_free.epoch_log = true;
  model_free.episodes.push_back(EpisodePoint{});
  const auto about = [](const std::string& text) { return ::testing::Contains(HasSubstr(text)); };
  const std::string agent_steps = "Table I here counts the first 3000 agent steps";
  const std::string environment_steps =
      "Model-free runs are counted over their first 3000 environment steps";
  EXPECT_THAT(SetupDifferences({mpc}, 3000, kConfigs), about(agent_steps));
  EXPECT_THAT(SetupDifferences({mpc}, 3000, kConfigs), Not(about(environment_steps)));
  EXPECT_THAT(SetupDifferences({model_free}, 3000, kConfigs), about(environment_steps));
  EXPECT_THAT(SetupDifferences({model_free}, 3000, kConfigs), Not(about(agent_steps)));
  const std::vector<std::string> both = SetupDifferences({mpc, model_free}, 3000, kConfigs);
  EXPECT_THAT(both, about(agent_steps));
  EXPECT_THAT(both, about(environment_steps));
}

// Where each run was made travels with its logs, and the report says it: each setup with its
// runs, a run resumed elsewhere, runs that kept no record.
TEST_F(ReportTest, WhereTheRunsWereMadeIsKeptAndSaid) {
  NumericsSetup here;
  here.cmbrl = "0.1.0 (abc)";
  here.cpu = "AMD EPYC";
  here.blas_core = "Haswell";
  here.blas_threads = 1;
  here.torch_threads = 1;
  NumericsSetup there = here;
  there.cpu = "Intel Xeon";
  const fs::path runs_dir = sweep_ / "runs";
  RecordRunSession(RunDirectory(runs_dir / "PointGoal1-rce-s0"), 0, here);
  RecordRunSession(RunDirectory(runs_dir / "PointGoal1-rce-s1"), 0, here);
  RecordRunSession(RunDirectory(runs_dir / "PointGoal1-rce-s1"), 100, there);
  RecordRunSession(RunDirectory(runs_dir / "PointGoal1-cem-s0"), 0, there);

  const fs::path out = sweep_ / "report";
  KeepRunLogs(ReadSweep(sweep_.string()), out.string());
  EXPECT_TRUE(fs::exists(out / "run-logs" / "PointGoal1-rce-s1" / "sessions.jsonl"));
  EXPECT_FALSE(fs::exists(out / "run-logs" / "PointGoal1-cem-s1" / "sessions.jsonl"));
  const std::vector<RunRecord> runs = ReadSweep(out.string());
  const auto run = std::find_if(runs.begin(), runs.end(),
                                [](const RunRecord& r) { return r.name == "PointGoal1-rce-s1"; });
  ASSERT_NE(run, runs.end());
  ASSERT_EQ(run->sessions.size(), 2u);
  EXPECT_EQ(run->sessions[1].setup, there);

  const std::vector<std::string> notes = WhereRunsWereMade(runs);
  ASSERT_EQ(notes.size(), 4u);
  // Runs in name order: CarGoal2 (none recorded), then PointGoal1-cem-s0 (there) first.
  EXPECT_THAT(notes[0], HasSubstr("CPU 'Intel Xeon'"));
  EXPECT_THAT(notes[0], HasSubstr(": 2 runs (PointGoal1-cem-s0, PointGoal1-rce-s1)."));
  EXPECT_THAT(notes[1], HasSubstr("CPU 'AMD EPYC'"));
  EXPECT_THAT(notes[1], HasSubstr(": 2 runs (PointGoal1-rce-s0, PointGoal1-rce-s1)."));
  EXPECT_THAT(notes[2],
              HasSubstr("PointGoal1-rce-s1 at step 100 (cpu 'AMD EPYC' -> 'Intel Xeon')"));
  EXPECT_THAT(notes[3], HasSubstr("Not recorded (begun before runs kept sessions.jsonl): 4 runs"));
}

}  // namespace
}  // namespace cmbrl

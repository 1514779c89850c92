#include "cmbrl/sweep/sweep.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cmbrl/core/shell.h"
#include "cmbrl/learners/mpc/mpc_learner.h"
#include "cmbrl/run/run_directory.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ErrorMessage;

SweepGrid PaperGrid() {
  SweepGrid grid;
  grid.tasks = {"PointGoal1", "CarGoal2"};
  grid.planners = {"rce", "random"};
  grid.seeds = {0, 1};
  grid.config_dir = CMBRL_SOURCE_DIR "/configs";
  return grid;
}

TEST(SweepTest, PlansEveryRunOfTheGridWithItsConfig) {
  const std::vector<SweepRun> runs = PlanSweep(PaperGrid(), "/tmp/sweep");
  ASSERT_EQ(runs.size(), 8u);
  EXPECT_EQ(runs[0].name, "pointgoal1-rce-s0");
  EXPECT_EQ(runs[0].run_dir, "/tmp/sweep/runs/pointgoal1-rce-s0");
  ASSERT_EQ(runs[0].config_paths.size(), 1u);
  EXPECT_THAT(runs[0].config_paths[0], ::testing::EndsWith("configs/pointgoal1-rce.yaml"));
  EXPECT_EQ(runs[7].name, "cargoal2-random-s1");
  EXPECT_EQ(runs[7].seed, 1u);
  EXPECT_EQ(StatusOf(runs[0]), RunStatus::kNew);
  EXPECT_EQ(TrainArguments(runs[7], PaperGrid()),
            (std::vector<std::string>{"train", "--config", runs[7].config_paths[0], "--seed",
                                      "1", "--out", runs[7].run_dir}));
}

// A family composed over every preset, overrides for every run, and axes whose combinations
// each make their own runs, named by their values.
TEST(SweepTest, AxesMakeARunPerCombinationAfterTheGridsOverrides) {
  SweepGrid grid = PaperGrid();
  grid.tasks = {"PointGoal2"};
  grid.planners = {"rce"};
  grid.seeds = {4};
  grid.overlays = {CMBRL_SOURCE_DIR "/configs/cpu.yaml"};
  grid.overrides = {"training.total_steps=2000"};
  grid.axes = {{"classifier.threshold", {"0.3", "0.5"}},
               {"ensemble.hidden_sizes", {"[128, 128]", "[256, 256, 256]"}}};
  const std::vector<SweepRun> runs = PlanSweep(grid, "/tmp/sweep");
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[0].name, "pointgoal2-rce-threshold=0.3-hidden_sizes=128x128-s4");
  EXPECT_EQ(runs[3].name, "pointgoal2-rce-threshold=0.5-hidden_sizes=256x256x256-s4");
  EXPECT_EQ(runs[1].overrides,
            (std::vector<std::string>{"training.total_steps=2000", "classifier.threshold=0.3",
                                      "ensemble.hidden_sizes=[256, 256, 256]"}));
  EXPECT_EQ(NewRunArguments(runs[1]),
            (std::vector<std::string>{"train", "--config", runs[1].config_paths[0],
                                      CMBRL_SOURCE_DIR "/configs/cpu.yaml", "--set",
                                      "training.total_steps=2000", "classifier.threshold=0.3",
                                      "ensemble.hidden_sizes=[256, 256, 256]", "--seed", "4",
                                      "--out", runs[1].run_dir}));
  grid.axes = {{"classifier.threshold", {"0.3", "0.3"}}};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("repeats a value"));
  grid.axes = {{"classifier.threshold", {}}};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("has no values"));
  grid.axes = {};
  grid.overlays = {"/nonexistent/family.yaml"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }),
              HasSubstr("no config '/nonexistent/family.yaml'"));
}

TEST(SweepTest, BadGridsAreNamed) {
  SweepGrid grid = PaperGrid();
  grid.tasks = {"AntGoal1"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("unknown task 'AntGoal1'"));
  grid = PaperGrid();
  grid.planners = {"mppi"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("unknown planner or algorithm 'mppi'"));
  grid = PaperGrid();
  grid.seeds = {3, 3};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("repeat a seed"));
  // One run named twice would get two processes (the probe's --tasks PointGoal1 PointGoal1).
  grid = PaperGrid();
  grid.tasks = {"PointGoal1", "PointGoal1"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("repeat a task"));
  grid = PaperGrid();
  grid.planners = {"rce", "cem", "rce"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }), HasSubstr("repeat a method"));
  grid = PaperGrid();
  grid.config_dir = "/nonexistent";
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }),
              HasSubstr("no config '/nonexistent/pointgoal1-rce.yaml' for PointGoal1 with rce"));
  // A run is what its name says: a preset that trains another method or task is refused.
  const fs::path presets = testing::TestTempDir() / "contradicting";
  fs::create_directories(presets);
  std::ofstream(presets / "pointgoal1-rce.yaml") << "task: PointGoal1\nplanner: cem\n";
  std::ofstream(presets / "pointgoal1-cem.yaml") << "task: CarGoal1\nplanner: cem\n";
  grid = PaperGrid();
  grid.tasks = {"PointGoal1"};
  grid.config_dir = presets.string();
  grid.planners = {"rce"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }),
              HasSubstr("trains task 'PointGoal1' with 'cem', not 'PointGoal1' with 'rce'"));
  grid.planners = {"cem"};
  EXPECT_THAT(ErrorMessage([&] { PlanSweep(grid, "s"); }),
              HasSubstr("trains task 'CarGoal1' with 'cem', not 'PointGoal1' with 'cem'"));
}

TEST(SweepTest, SlurmScriptHasOneArrayTaskPerRun) {
  SweepGrid grid = PaperGrid();
  grid.steps = 3000;
  const std::vector<SweepRun> runs = PlanSweep(grid, "/tmp/sweep");
  const std::string script = SlurmScript(runs, grid, "/tmp/sweep", "/opt/cmbrl/bin/cmbrl");
  EXPECT_THAT(script, HasSubstr("#SBATCH --array=0-7\n"));
  EXPECT_THAT(script, HasSubstr("cmbrl='/opt/cmbrl/bin/cmbrl'\n"));
  EXPECT_THAT(script, HasSubstr("  7) run_dir='/tmp/sweep/runs/cargoal2-random-s1'; start=('train' "
                                 "'--config' '" CMBRL_SOURCE_DIR "/configs/cargoal2-random.yaml' "
                                 "'--seed' '1' '--out' '/tmp/sweep/runs/cargoal2-random-s1');;\n"));
  EXPECT_THAT(script, HasSubstr("train --resume \"$run_dir\" --steps 3000)\n"));
  EXPECT_THAT(script, HasSubstr("command=(\"$cmbrl\" \"${start[@]}\" --steps 3000)\n"));
  // Warned before the time limit, the task stops its run and requeues itself.
  EXPECT_THAT(script,
              HasSubstr(fmt::format("#SBATCH --signal=B:USR1@{}\n", kSlurmTimeLimitLeadSeconds)));
  EXPECT_THAT(script, HasSubstr("scontrol requeue \"$SLURM_JOB_ID\""));
  EXPECT_THAT(script, HasSubstr("#SBATCH --output=/tmp/sweep/logs/slurm-%a.log\n"));
  // A folder with a space: the #SBATCH line quotes it (sbatch removes the quotes), a double
  // quote is refused by name.
  const std::string spaced = SlurmScript(runs, grid, "/tmp/my sweep", "/opt/cmbrl/bin/cmbrl");
  EXPECT_THAT(spaced, HasSubstr("#SBATCH --output=\"/tmp/my sweep/logs/slurm-%a.log\"\n"));
  EXPECT_THAT(ErrorMessage([&] { SlurmScript(runs, grid, "/tmp/a\"b", "/opt/cmbrl"); }),
              HasSubstr("cannot hold a double quote"));
}

TEST(SweepTest, ShellWordsPasteAsOneWord) {
  EXPECT_EQ(ShellWord("runs/q-1"), "runs/q-1");
  EXPECT_EQ(ShellWord("my runs/q"), "'my runs/q'");
  EXPECT_EQ(ShellWord("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellWord(""), "''");
  EXPECT_EQ(ShellQuote("a b"), "'a b'");
}

TEST(SweepTest, ARestartWithOtherSettingsIsRefused) {
  const std::string dir = testing::TestTempPath("sweep_settings");
  fs::remove_all(dir);
  SweepGrid grid = PaperGrid();
  grid.steps = 3000;
  RecordOrCheckSweep(grid, dir);
  RecordOrCheckSweep(grid, dir);  // the same settings again: fine
  grid.steps = 2000;
  EXPECT_THAT(ErrorMessage([&] { RecordOrCheckSweep(grid, dir); }),
              HasSubstr("this sweep was started with steps 3000, now steps is 2000"));
  grid.steps = std::nullopt;  // the configs' budgets: another grid
  EXPECT_THAT(ErrorMessage([&] { RecordOrCheckSweep(grid, dir); }),
              HasSubstr("this sweep was started with steps 3000, now steps is null"));
  grid.config_dir = CMBRL_SOURCE_DIR "/configs/ppo";
  grid.steps = 5000;
  EXPECT_THAT(ErrorMessage([&] { RecordOrCheckSweep(grid, dir); }),
              HasSubstr("this sweep was started with config_dir"));
  grid = PaperGrid();
  grid.steps = 3000;
  grid.overlays = {CMBRL_SOURCE_DIR "/configs/cpu.yaml"};
  EXPECT_THAT(ErrorMessage([&] { RecordOrCheckSweep(grid, dir); }),
              HasSubstr("this sweep was started with overlays []"));
  // A larger budget continues the sweep: recorded, and every started run resumes to it.
  grid = PaperGrid();
  grid.steps = 5000;
  RecordOrCheckSweep(grid, dir);
  std::ifstream recorded(fs::path(dir) / "sweep.json");
  EXPECT_THAT(std::string(std::istreambuf_iterator<char>(recorded), {}),
              HasSubstr("\"steps\": 5000"));
  const std::vector<SweepRun> runs = PlanSweep(grid, dir);
  fs::create_directories(runs[0].run_dir);
  std::ofstream(fs::path(runs[0].run_dir) / "config.yaml") << "training: {total_steps: 3000}\n";
  std::ofstream(fs::path(runs[0].run_dir) / "progress.csv")
      << ProgressCsvHeader() << "\n1,1,0,0,3001,0,0,0,0,0,0,0,100,0,0,0,0\n";
  EXPECT_EQ(StatusOf(runs[0]), RunStatus::kFinished);  // by its own budget
  EXPECT_EQ(StatusOf(runs[0], 5000), RunStatus::kStarted);
  EXPECT_EQ(TrainArguments(runs[0], grid),
            (std::vector<std::string>{"train", "--resume", runs[0].run_dir, "--steps", "5000"}));
}

// A model-free run's progress has a row per epoch: finished once its last epoch reaches the
// budget, like an MPC run's last episode.
TEST(SweepTest, AModelFreeRunIsFinishedByItsEpochs) {
  const std::string dir = testing::TestTempPath("sweep_model_free");
  fs::remove_all(dir);
  SweepGrid grid = PaperGrid();
  grid.planners = {"cpo"};
  const std::vector<SweepRun> runs = PlanSweep(grid, dir);
  fs::create_directories(runs[0].run_dir);
  std::ofstream(fs::path(runs[0].run_dir) / "config.yaml")
      << "variant: paper-lidar\nalgorithm: cpo\ntraining: {total_steps: 60000}\n";
  const auto write_epochs = [&](int epochs) {
    std::ofstream progress(fs::path(runs[0].run_dir) / "progress.csv");
    progress << "Epoch,AverageEpRet,AverageEpCost,EpLen,CumulativeCost,TotalEnvInteracts\n";
    for (int e = 1; e <= epochs; ++e) {
      progress << e << ",1,2,300," << 200 * e << "," << 30000 * e << "\n";
    }
  };
  write_epochs(1);
  EXPECT_EQ(StatusOf(runs[0]), RunStatus::kStarted);
  write_epochs(2);
  EXPECT_EQ(StatusOf(runs[0]), RunStatus::kFinished);
}

// How far each run has got, for `cmbrl sweep --status`: a new run's budget as the sweep would
// compose its configs and overrides, a started run's steps and training time from its progress
// (or its checkpoint, when ahead) and budget from its config.yaml, and the grid's budget over
// both.
TEST(SweepTest, ProgressSaysTheStepsReachedAndTheBudget) {
  const std::string dir = testing::TestTempPath("sweep_progress");
  fs::remove_all(dir);
  SweepGrid grid = PaperGrid();
  grid.overrides = {"training.total_steps=4000"};
  const std::vector<SweepRun> runs = PlanSweep(grid, dir);
  const RunProgress fresh = ProgressOf(runs[0]);
  EXPECT_EQ(fresh.status, RunStatus::kNew);
  EXPECT_EQ(fresh.steps, 0);
  EXPECT_EQ(fresh.budget, 4000);  // the override over the preset's 10,000
  EXPECT_EQ(ProgressOf(runs[0], 3000).budget, 3000);
  EXPECT_STREQ(RunStatusName(fresh.status), "new");
  fs::create_directories(runs[1].run_dir);
  std::ofstream(fs::path(runs[1].run_dir) / "config.yaml") << "training: {total_steps: 3000}\n";
  std::ofstream(fs::path(runs[1].run_dir) / "progress.csv")
      << ProgressCsvHeader() << "\n1,1,0,0,1000,0,30.5,0,0,0,0,0,1000,0,0,0,0\n"
      << "1,2,0,0,2000,0,61.25,0,0,0,0,0,1000,0,0,0,0\n";
  EXPECT_FALSE(fresh.seconds.has_value());
  const RunProgress started = ProgressOf(runs[1]);
  EXPECT_EQ(started.status, RunStatus::kStarted);
  EXPECT_EQ(started.steps, 2000);
  EXPECT_EQ(started.seconds, 61.25);  // its last row's Time
  EXPECT_EQ(started.budget, 3000);  // its own config's, not the grid's override
  EXPECT_STREQ(RunStatusName(started.status), "started");
  const RunProgress done = ProgressOf(runs[1], 2000);
  EXPECT_EQ(done.status, RunStatus::kFinished);
  EXPECT_STREQ(RunStatusName(done.status), "finished");
  // A row half written by a killed process: started, its steps unknown until resumed.
  std::ofstream(fs::path(runs[1].run_dir) / "progress.csv", std::ios::app) << "1,3,0,0,2";
  EXPECT_EQ(ProgressOf(runs[1]).status, RunStatus::kStarted);
  EXPECT_EQ(ProgressOf(runs[1]).steps, 0);
  // A checkpoint taken in the middle of an episode is ahead of the rows: its steps count, and
  // the run is not finished before its episode is, even past its budget.
  std::ofstream(fs::path(runs[1].run_dir) / "progress.csv")
      << ProgressCsvHeader() << "\n1,1,0,0,1000,0,30.5,0,0,0,0,0,1000,0,0,0,0\n";
  const auto no_files = [](const fs::path&, const fs::path&) {};
  WriteCheckpoint(RunDirectory(runs[1].run_dir), 1, 75.0, no_files, 1234);
  EXPECT_EQ(ProgressOf(runs[1]).steps, 1234);
  EXPECT_EQ(ProgressOf(runs[1]).seconds, 75.0);  // the checkpoint's training time, ahead too
  EXPECT_EQ(ProgressOf(runs[1], 1200).status, RunStatus::kStarted);
  // A manifest without them (before v0.9), or behind the rows, leaves the rows' steps.
  WriteCheckpoint(RunDirectory(runs[1].run_dir), 1, 0.0, no_files);
  EXPECT_EQ(ProgressOf(runs[1]).steps, 1000);
  WriteCheckpoint(RunDirectory(runs[1].run_dir), 1, 0.0, no_files, 900);
  EXPECT_EQ(ProgressOf(runs[1]).steps, 1000);
  EXPECT_EQ(ProgressOf(runs[1]).seconds, 30.5);
}

// A run's logs as a report keeps them (run-logs/<name>): config.yaml and progress.csv.
void WriteRunLog(const fs::path& dir, int budget, int steps_reached) {
  fs::create_directories(dir);
  std::ofstream(dir / "config.yaml") << "training: {total_steps: " << budget << "}\n";
  std::ofstream progress(dir / "progress.csv");
  progress << ProgressCsvHeader() << "\n";
  for (int end = 1000, episode = 1; end <= steps_reached; end += 1000, ++episode) {
    progress << "1," << episode << ",0,0," << end << ",0,0,0,0,0,0,0,1000,0,0,0,0\n";
  }
}

TEST(SweepTest, RunsFinishedInTheReportAreNotRunAgain) {
  const std::string dir = testing::TestTempPath("sweep_reported");
  fs::remove_all(dir);
  SweepGrid grid = PaperGrid();
  grid.overrides = {"training.total_steps=2000"};
  grid.reported_dir = (fs::path(dir) / "report" / "run-logs").string();
  const std::vector<SweepRun> runs = PlanSweep(grid, dir);
  ASSERT_EQ(runs[0].reported_run_dir, (fs::path(grid.reported_dir) / runs[0].name).string());
  WriteRunLog(runs[0].reported_run_dir, 2000, 2000);  // finished on another machine
  const RunProgress reported = ProgressOf(runs[0]);
  EXPECT_EQ(reported.status, RunStatus::kFinished);
  EXPECT_TRUE(reported.in_report);
  EXPECT_EQ(reported.steps, 2000);
  EXPECT_EQ(StatusOf(runs[0]), RunStatus::kFinished);
  EXPECT_FALSE(ProgressOf(runs[2]).in_report);  // in neither folder: new

  std::vector<std::string> events;
  const auto record = [&](const SweepEvent& event) {
    events.push_back(event.run + ": " + event.status);
  };
  {
    const PreparedSweep prepared = PrepareSweep(grid, dir, "cmbrl", record);
    EXPECT_EQ(prepared.already_finished, 1);
    EXPECT_EQ(prepared.unfinished.size(), runs.size() - 1);
    EXPECT_EQ(prepared.unfinished.front(), 1u);
    EXPECT_THAT(events,
                ::testing::ElementsAre(runs[0].name + ": already finished (in the report)"));
    // The folder is the sweep's while it is prepared: a second sweep of it is refused.
    EXPECT_THAT(ErrorMessage([&] { PrepareSweep(grid, dir, "cmbrl", record); }),
                HasSubstr("is in use by another cmbrl process"));
  }

  // Half done elsewhere: its checkpoints are not here, so the sweep says so and starts nothing.
  WriteRunLog(runs[1].reported_run_dir, 2000, 1000);
  const RunProgress half = ProgressOf(runs[1]);
  EXPECT_EQ(half.status, RunStatus::kNew);
  EXPECT_TRUE(half.in_report);
  EXPECT_EQ(half.steps, 1000);
  const std::string refused = ErrorMessage([&] { PrepareSweep(grid, dir, "cmbrl", record); });
  EXPECT_THAT(refused, HasSubstr("run '" + runs[1].name + "' is in the report's logs"));
  EXPECT_THAT(refused, HasSubstr("at step 1000 of 2000"));
  EXPECT_THAT(refused, HasSubstr("remove its logs from the report"));

  // The sweep's own folder comes first: a run there is judged by its own progress.
  WriteRunLog(runs[1].run_dir, 2000, 1000);
  const RunProgress local = ProgressOf(runs[1]);
  EXPECT_EQ(local.status, RunStatus::kStarted);
  EXPECT_FALSE(local.in_report);
  fs::remove_all(runs[1].reported_run_dir);
  EXPECT_EQ(PrepareSweep(grid, dir, "cmbrl", record).unfinished.size(), runs.size() - 1);
}

TEST(SweepTest, EachRunAtATimeGetsItsOwnCpus) {
  using Shares = std::vector<std::vector<int>>;
  EXPECT_EQ(CpuShares({0, 1}, 2), (Shares{{0}, {1}}));
  EXPECT_EQ(CpuShares({0, 1, 2, 3, 4}, 2), (Shares{{0, 1}, {2, 3}}));  // CPU 4 stays unused
  EXPECT_EQ(CpuShares({2, 5, 7}, 1), (Shares{{2, 5, 7}}));             // a taskset's CPUs
  EXPECT_EQ(CpuShares({0, 1}, 3), Shares{});  // more jobs than CPUs: they share all
  EXPECT_THAT(ErrorMessage([] { CpuShares({0}, 0); }), HasSubstr("jobs is 0: expected"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/train/trainer.h"

#include <fmt/ranges.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <iterator>
#include <sstream>
#include <thread>

#include "cmbrl/core/files.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/learners/mpc/mpc_learner.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"
#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/transition_buffer.h"
#include "cmbrl/run/progress_table.h"
#include "cmbrl/run/run_directory.h"
#include "cmbrl/run/run_sessions.h"
#include "cmbrl/train/current_setup.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using testing::ErrorMessage;

// A file's whole contents, byte for byte ("" when it is missing).
std::string FileBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Seconds of work: tiny networks, a short horizon, a handful of pre-training episodes.
TrainConfig TinyConfig(const std::string& planner) {
  return ParseTrainConfig(fmt::format(R"(
planner: {}
seed: 3
training: {{pretrain_episodes: 6, pretrain_steps: 20, episodes_per_epoch: 2, total_steps: 400}}
ensemble: {{hidden_sizes: [16], max_epochs: 5}}
classifier: {{rounds: 10}}
planning: {{horizon: 3, population: 24, elites: 6, min_feasible_elites: 3, max_iterations: 2,
           random_samples: 50}}
)",
                                      planner),
                          "tiny");
}

// A run folder, not yet made, in the test's own folder (removed when the test passes); a loop
// that asks for one name again gets it empty.
std::string TempRunDir(const std::string& name) {
  const std::string dir = testing::TestTempPath(name);
  fs::remove_all(dir);
  return dir;
}

// progress.csv without the columns of clock figures, found by name in its header: Time,
// MsPerPlan and CpuTime.
std::vector<std::string> RowsWithoutTimes(const std::string& run_dir) {
  std::ifstream in(fs::path(run_dir) / "progress.csv");
  std::vector<std::string> rows;
  std::vector<bool> dropped;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    for (size_t column = 0; std::getline(stream, cell, ','); ++column) {
      if (rows.empty()) {
        dropped.push_back(cell == "Time" || cell == "MsPerPlan" || cell == "CpuTime");
      }
      if (column >= dropped.size() || !dropped[column]) cells.push_back(cell);
    }
    rows.push_back(fmt::format("{}", fmt::join(cells, ",")));
  }
  return rows;
}

// Starts a run and crashes it (an exception out of Run) right after its `rows`-th progress row
// is written, before that row's checkpoint.
void CrashAfterRows(const TrainConfig& config, const std::string& dir, int rows) {
  struct Crash {};
  try {
    int units = 0;
    Trainer::Start(config, dir)->Run([&](const ProgressSummary&) {
      if (++units == rows) throw Crash{};
    });
    FAIL() << "expected the simulated crash";
  } catch (const Crash&) {
  }
}

TEST(TrainerTest, AShortRunWritesEveryFile) {
  const std::string dir = TempRunDir("files");
  std::vector<ProgressRow> seen;
  const std::unique_ptr<Trainer> trainer = Trainer::Start(TinyConfig("rce"), dir);
  trainer->Run([&](const ProgressSummary& unit) {
    seen.push_back(dynamic_cast<const MpcLearner&>(trainer->learner()).last_row());
    EXPECT_EQ(unit.steps, seen.back().total_env_interacts);
    EXPECT_EQ(unit.epoch, seen.back().epoch);
  });
  EXPECT_TRUE(fs::exists(fs::path(dir) / "config.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "state.json"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "ensemble.pt"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "classifier.json"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "transitions.bin"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "manifest.json"));
  // 400 agent steps of whole episodes of about 100: four or five rows, one per episode.
  const std::vector<std::string> rows = RowsWithoutTimes(dir);
  ASSERT_GE(seen.size(), 4u);
  EXPECT_EQ(rows.size(), seen.size() + 1);
  EXPECT_EQ(rows[0],
            "Epoch,Episode,EpRet,EpCost,TotalEnvInteracts,PretrainInteracts,DynamicsValMSE,"
            "ClassifierSafeAcc,ClassifierUnsafeAcc,FeasibleFraction,Steps,GoalsMet,HazardSteps,"
            "VaseSteps");
  EXPECT_GE(seen.back().total_env_interacts, 400);
  EXPECT_EQ(seen[0].epoch, 1);
  EXPECT_EQ(seen[2].epoch, 2);  // two episodes per epoch
  EXPECT_GT(seen[0].pretrain_interacts, 0);
  EXPECT_EQ(seen[0].pretrain_interacts, seen.back().pretrain_interacts);
  EXPECT_TRUE(std::isfinite(seen[0].dynamics_validation_mse));
  EXPECT_GT(seen[0].ms_per_plan, 0.0);
  // Every violating step is in a hazard or at a vase (no physics errors here), and each count is
  // at most the episode's violations.
  for (const ProgressRow& row : seen) {
    EXPECT_LE(row.hazard_steps, row.episode_cost);
    EXPECT_LE(row.vase_steps, row.episode_cost);
    EXPECT_GE(row.hazard_steps + row.vase_steps, row.episode_cost);
  }
  // The resolved config reads back as the same config.
  EXPECT_EQ(TrainConfigToYaml(LoadTrainConfig((fs::path(dir) / "config.yaml").string())),
            TrainConfigToYaml(TinyConfig("rce")));
  // The session's wall time, split into its parts: every part measured, none negative, and the
  // parts that ran (planning, steps, fits, checkpoints) took time.
  const auto split = trainer->TimeSplit();
  std::vector<std::string> parts;
  for (const auto& [part, seconds] : split) {
    parts.push_back(part);
    EXPECT_GE(seconds, 0.0) << part;
    if (part != "other") {
      EXPECT_GT(seconds, 0.0) << part;
    }
  }
  EXPECT_EQ(parts, (std::vector<std::string>{"planning", "environment", "dynamics_fits",
                                             "classifier_fits", "checkpoints", "other"}));
  // Planning is timed around each action, and each action's own clock sits inside it.
  double plan_ms = 0.0;
  for (const ProgressRow& row : seen) plan_ms += row.ms_per_plan * row.steps;
  EXPECT_GE(split[0].second * 1e3, plan_ms * 0.999);
}

// Labels beside stored transitions only, as the original (facts B4), or on every agent step.
TEST(TrainerTest, ClassifierLabelsFollowTheStoredTransitionsUnlessEveryStepIsAsked) {
  for (const bool every_step : {false, true}) {
    TrainConfig config = TinyConfig("cem");
    config.training.label_every_step = every_step;
    config.training.total_steps = 150;
    const std::string dir = TempRunDir(every_step ? "labels_every" : "labels_stored");
    Trainer::Start(config, dir)->Run();
    const fs::path checkpoint = fs::path(dir) / "checkpoint";
    TransitionBuffer transitions(24, 2);
    transitions.Load((checkpoint / "transitions.bin").string());
    LabeledStateBuffer labels(24);
    labels.Load((checkpoint / "labeled_states.bin").string());
    const int labelled = labels.safe_size() + labels.unsafe_size();
    // Every episode ends with a step that is not stored (the end), so every-step labelling keeps
    // at least one label per episode more.
    if (every_step) {
      EXPECT_GT(labelled, transitions.size());
    } else {
      EXPECT_EQ(labelled, transitions.size());
    }
  }
}

TEST(TrainerTest, SameSeedGivesTheSameRows) {
  const std::string a = TempRunDir("same_a"), b = TempRunDir("same_b");
  Trainer::Start(TinyConfig("cem"), a)->Run();
  Trainer::Start(TinyConfig("cem"), b)->Run();
  EXPECT_EQ(RowsWithoutTimes(a), RowsWithoutTimes(b));
}

// CpuTime is the CPU time of the run's sessions: it rises row by row, carries on across a resume
// from what the checkpoint recorded (the work a crash threw away not counted), and a process
// cannot use more CPU seconds than its cores give it in the wall seconds of Time. The trainer
// says what its own session used.
TEST(TrainerTest, CpuTimeCountsTheCpuSecondsOfEverySession) {
  const std::string dir = TempRunDir("cpu_time");
  CrashAfterRows(TinyConfig("cem"), dir, 2);  // the checkpoint covers the first row
  const nlohmann::json manifest =
      nlohmann::json::parse(FileBytes(fs::path(dir) / "checkpoint" / "manifest.json"));
  ASSERT_TRUE(manifest.contains("cpu_seconds"));
  const double checkpointed = manifest.at("cpu_seconds").get<double>();
  const std::unique_ptr<Trainer> resumed = Trainer::Resume(dir);
  resumed->Run();
  const ProgressTable table = ProgressTable::Read(fs::path(dir) / "progress.csv");
  ASSERT_GE(table.rows(), 4u);
  const size_t cpu = table.Column("CpuTime", "the run's CPU seconds");
  const size_t time = table.Column("Time", "the run's wall seconds");
  EXPECT_EQ(cpu + 1, table.header().size());  // the last column
  const double cores = std::max(1u, std::thread::hardware_concurrency());
  // The rows print CPU seconds to 3 decimals; the manifest keeps them whole.
  const double rounding = 0.0005;
  for (size_t row = 0; row < table.rows(); ++row) {
    const double seconds = table.Number(row, cpu);
    EXPECT_GT(seconds, 0.0) << "row " << row;
    if (row > 0) {
      EXPECT_GE(seconds, table.Number(row - 1, cpu)) << "row " << row;
      EXPECT_GE(seconds, checkpointed - rounding) << "row " << row;
    }
    EXPECT_LE(seconds, table.Number(row, time) * cores + 0.01) << "row " << row;
  }
  EXPECT_LE(table.Number(0, cpu), checkpointed + rounding);
  // The resumed session's own CPU seconds (cmbrl train's summary): what the last row added to
  // the checkpoint's, and a little more for the work after it.
  const double this_session = resumed->CpuSecondsThisSession();
  const double last = table.Number(table.rows() - 1, cpu);
  EXPECT_GT(this_session, 0.0);
  EXPECT_GE(checkpointed + this_session, last - rounding);
  EXPECT_LE(this_session, table.Number(table.rows() - 1, time) * cores + 0.01);
}

TEST(TrainerTest, ResumingAfterACrashGivesTheSameRows) {
  const std::string whole = TempRunDir("whole"), crashed = TempRunDir("crashed");
  Trainer::Start(TinyConfig("rce"), whole)->Run();
  // Stop after the third row is written but before its checkpoint: the worst moment.
  CrashAfterRows(TinyConfig("rce"), crashed, 3);
  EXPECT_EQ(RowsWithoutTimes(crashed).size(), 4u);  // header + 3 rows, the third uncovered
  const std::unique_ptr<Trainer> resumed = Trainer::Resume(crashed);
  const std::int64_t resumed_at = resumed->steps_done();
  resumed->Run();
  EXPECT_EQ(RowsWithoutTimes(crashed), RowsWithoutTimes(whole));
  // Each session is on record, the resume at the checkpoint's step, on the same setup.
  EXPECT_TRUE(resumed->setup_changes().empty());
  EXPECT_EQ(ReadRunSessions(RunDirectory(whole)).size(), 1u);
  const std::vector<RunSession> sessions = ReadRunSessions(RunDirectory(crashed));
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[0].steps_done, 0);
  EXPECT_GT(resumed_at, 0);
  EXPECT_EQ(sessions[1].steps_done, resumed_at);
  EXPECT_EQ(sessions[1].setup, CurrentNumericsSetup("cpu"));
}

// Writes the run's checkpoint again over its files as they are now (the same learner files,
// rows and seconds): what a run whose files were written so by an older version or on another
// machine would hold. Through WriteCheckpoint, so that the manifest is one the run would write.
void RewriteCheckpoint(const std::string& dir) {
  const fs::path manifest = fs::path(dir) / "checkpoint" / "manifest.json";
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(manifest));
  WriteCheckpoint(RunDirectory(dir), json.at("rows").get<std::int64_t>(),
                  json.at("elapsed_seconds").get<double>(),
                  [](const fs::path& folder, const fs::path& previous) {
                    for (const fs::directory_entry& file : fs::directory_iterator(previous)) {
                      if (file.path().filename() == "manifest.json") continue;
                      fs::copy_file(file.path(), folder / file.path().filename());
                    }
                  });
}

// A stopped run's checkpoint with an untouched copy beside it, for tests that damage its files
// one at a time and put them back between two damages.
struct KeptCheckpoint {
  KeptCheckpoint(const std::string& dir, const std::string& copy_name)
      : path(fs::path(dir) / "checkpoint"), saved(TempRunDir(copy_name)) {
    fs::copy(path, saved);
  }
  void Restore() const {
    fs::remove_all(path);
    fs::copy(saved, path);
  }
  const fs::path path;   // the run's checkpoint
  const fs::path saved;  // its copy
};

// Runs until `stop_at` agent steps are done, when the run stops at a checkpoint taken then;
// returns the steps done.
std::int64_t StopAt(std::unique_ptr<Trainer> trainer, std::int64_t stop_at) {
  RunOptions options;
  options.checkpoint_seconds = 1e9;  // no checkpoint but the one asked for
  options.stop_requested = [&] { return trainer->steps_done() >= stop_at; };
  trainer->Run(options);
  EXPECT_FALSE(trainer->learner().Finished());
  return trainer->steps_done();
}

TEST(TrainerTest, AnEpisodeStoppedBetweenTwoStepsResumesToTheSameRows) {
  for (const std::string planner : {"rce", "cem", "random"}) {
    SCOPED_TRACE(planner);
    TrainConfig config = TinyConfig(planner);
    config.planning.cross_entropy.warm_start =
        planner == "cem";               // a mean carried from plan to plan
    config.training.total_steps = 350;  // spent in the middle of the fourth episode
    const std::string whole = TempRunDir("open_whole_" + planner);
    const std::string stopped = TempRunDir("open_stopped_" + planner);
    Trainer::Start(config, whole)->Run();
    const fs::path checkpoint = fs::path(stopped) / "checkpoint";
    // In the second episode (of about 100 steps), then in the last one after the budget is
    // spent: that episode must still end.
    EXPECT_EQ(StopAt(Trainer::Start(config, stopped), 150), 150);
    EXPECT_EQ(RowsWithoutTimes(stopped).size(), 2u);  // header and the first episode
    const nlohmann::json open = nlohmann::json::parse(std::ifstream(checkpoint / "episode.json"));
    EXPECT_GT(open.at("steps").get<int>(), 0);
    EXPECT_LT(open.at("steps").get<int>(), 100);
    EXPECT_TRUE(fs::exists(checkpoint / "episode_env.bin"));
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(checkpoint / "manifest.json")).at("steps_done"),
              150);
    EXPECT_EQ(fs::exists(checkpoint / "planner_carried.pt"), planner == "cem");
    EXPECT_EQ(StopAt(Trainer::Resume(stopped), 360), 360);
    Trainer::Resume(stopped)->Run();
    EXPECT_EQ(RowsWithoutTimes(stopped), RowsWithoutTimes(whole));
    EXPECT_FALSE(fs::exists(checkpoint / "episode.json"));  // the last checkpoint ends a unit
    EXPECT_EQ(ReadRunSessions(RunDirectory(stopped)).size(), 3u);
  }
}

// environment.previous_action: the run observes the Car's last action too, plans with it echoed
// into its predictions, and an episode stopped between two steps resumes to the same rows (the
// open episode's environment state holds the previous action).
TEST(TrainerTest, ARunThatObservesThePreviousActionResumesToTheSameRows) {
  TrainConfig config = TinyConfig("rce");
  config.task = "CarGoal1";
  config.training.total_steps = 250;
  TrainConfig plain = config;
  config.previous_action = true;
  const std::string whole = TempRunDir("previous_whole"), stopped = TempRunDir("previous_stop");
  const std::string without = TempRunDir("previous_without");
  Trainer::Start(config, whole)->Run();
  Trainer::Start(plain, without)->Run();
  EXPECT_EQ(StopAt(Trainer::Start(config, stopped), 130), 130);
  Trainer::Resume(stopped)->Run();
  EXPECT_EQ(RowsWithoutTimes(stopped), RowsWithoutTimes(whole));
  // The models see two more inputs, so the planned episodes differ.
  EXPECT_NE(RowsWithoutTimes(whole), RowsWithoutTimes(without));
  EXPECT_NE(FileBytes(fs::path(whole) / "config.yaml").find("previous_action: true"),
            std::string::npos);
}

// A stop asked for during a dynamics fit pauses it after the epoch under way, with a checkpoint
// that holds the open fit; the resume goes on with it, to the same rows. In the classifier's fit
// (seconds, not paused) a stop gives the unit up without a checkpoint, and the resume redoes it.
TEST(TrainerTest, AStopDuringAFitPausesItOrGivesTheUnitUpAndTheResumeGivesTheSameRows) {
  struct Case {
    int episode;             // the fit after this episode (0: the pre-training's)
    int dynamics_questions;  // answered false first: then the stop falls in the classifier's fit
  };
  for (const Case c : {Case{0, 0}, Case{2, 0}, Case{2, 2}, Case{2, 4}}) {
    SCOPED_TRACE(::testing::Message() << c.episode << " " << c.dynamics_questions);
    const std::string whole = TempRunDir("fit_whole"), stopped = TempRunDir("fit_stopped");
    Trainer::Start(TinyConfig("cem"), whole)->Run();
    std::unique_ptr<Trainer> trainer = Trainer::Start(TinyConfig("cem"), stopped);
    const auto& learner = dynamic_cast<const MpcLearner&>(trainer->learner());
    RunOptions options;
    options.checkpoint_seconds = 1e9;
    int asked_in_fit = 0;
    // The epoch's fit follows its second episode, whose row is then the learner's last.
    options.stop_requested = [&] {
      const bool in_fit =
          c.episode == 0 ? trainer->steps_done() == 0 : learner.last_row().episode == c.episode;
      return in_fit && ++asked_in_fit > c.dynamics_questions;
    };
    trainer->Run(options);
    EXPECT_FALSE(trainer->learner().Finished());
    // The tiny ensemble fits 5 epochs and is asked after the first 4.
    const bool classifier = c.dynamics_questions >= 4;
    const std::vector<std::string> rows = RowsWithoutTimes(stopped);
    if (classifier) {  // given up: the second episode's row is not written
      EXPECT_EQ(rows.size(), 2u);
      EXPECT_EQ(trainer->checkpointed_steps(), 100);
      EXPECT_THAT(ErrorMessage([&] { trainer->Run(); }), ::testing::HasSubstr("resume the run"));
    } else {  // paused: the episode's row and the open fit are checkpointed
      EXPECT_EQ(rows.size(), c.episode == 0 ? 1u : 3u);
      EXPECT_EQ(trainer->checkpointed_steps(), trainer->steps_done());
    }
    trainer.reset();
    Trainer::Resume(stopped)->Run();
    EXPECT_EQ(RowsWithoutTimes(stopped), RowsWithoutTimes(whole));
  }
}

// A crash between two agent steps, with a checkpoint after every step: the run resumes from the
// step before and writes the uninterrupted run's rows.
TEST(TrainerTest, CheckpointsAfterEveryStepSurviveACrashInTheMiddleOfAnEpisode) {
  const std::string whole = TempRunDir("every_whole"), crashed = TempRunDir("every_crashed");
  Trainer::Start(TinyConfig("rce"), whole)->Run();
  struct Crash {};
  std::unique_ptr<Trainer> trainer = Trainer::Start(TinyConfig("rce"), crashed);
  RunOptions options;
  options.checkpoint_seconds = 0.0;
  options.stop_requested = [&] {
    if (trainer->steps_done() == 237) throw Crash{};
    return false;
  };
  EXPECT_THROW(trainer->Run(options), Crash);
  trainer.reset();  // lets go of the run's lock
  const std::unique_ptr<Trainer> resumed = Trainer::Resume(crashed);
  EXPECT_EQ(resumed->steps_done(), 236);
  resumed->Run();
  EXPECT_EQ(RowsWithoutTimes(crashed), RowsWithoutTimes(whole));
}

TEST(TrainerTest, ACheckpointOfAnOpenEpisodeIsCheckedWhenRead) {
  const std::string dir = TempRunDir("open_damaged");
  TrainConfig config = TinyConfig("cem");
  config.planning.cross_entropy.warm_start = true;
  StopAt(Trainer::Start(config, dir), 150);
  const KeptCheckpoint kept(dir, "open_damaged_saved");
  const fs::path& checkpoint = kept.path;
  // Each file replaced by another, or by nothing (RewriteCheckpoint keeps the manifest's sums
  // true to the damaged files, so that the learner's own checks are what answers).
  fs::remove(checkpoint / "episode_env.bin");
  WriteFile(checkpoint / "episode_env.bin", "not a state");
  RewriteCheckpoint(dir);
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir); }),
              ::testing::AllOf(::testing::HasSubstr("episode_env.bin' is damaged"),
                               ::testing::HasSubstr("environment state")));
  kept.Restore();
  WriteFile(checkpoint / "episode.json", R"({"observation": [1, 2], "steps": 3})");
  RewriteCheckpoint(dir);
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir); }),
              ::testing::AllOf(::testing::HasSubstr("episode.json' is damaged"),
                               ::testing::HasSubstr("observation has 2 entries")));
  kept.Restore();
  SaveTensor(torch::zeros({7, 2}), (checkpoint / "planner_carried.pt").string());
  RewriteCheckpoint(dir);
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir); }),
              ::testing::AllOf(::testing::HasSubstr("planner_carried.pt' does not fit"),
                               ::testing::HasSubstr("expected float32 of shape (3, 2)")));
  kept.Restore();
  EXPECT_NO_THROW(Trainer::Resume(dir)->Run());
}

// A run resumed on another machine goes on, and says so: its rows from then on are not the
// uninterrupted run's.
TEST(TrainerTest, AResumeOnAnotherSetupIsNamed) {
  const std::string dir = TempRunDir("elsewhere");
  CrashAfterRows(TinyConfig("cem"), dir, 2);
  const fs::path sessions = RunDirectory(dir).sessions_file();
  std::ifstream in(sessions);
  nlohmann::json first = nlohmann::json::parse(in);
  in.close();
  first["cpu"] = "Another CPU";
  std::ofstream(sessions) << first.dump() << "\n";
  RewriteCheckpoint(dir);  // as if the first session had run there
  {
    const std::unique_ptr<Trainer> resumed = Trainer::Resume(dir);
    EXPECT_THAT(resumed->setup_changes(),
                ::testing::ElementsAre(
                    fmt::format("cpu 'Another CPU' -> '{}'", CurrentNumericsSetup("cpu").cpu)));
    resumed->Run();
  }
  // A finished run asked to go on records no session.
  EXPECT_TRUE(Trainer::Resume(dir)->setup_changes().empty());
  EXPECT_EQ(ReadRunSessions(RunDirectory(dir)).size(), 2u);
}

// A run begun by a version that wrote fewer columns (here without the last two) keeps its
// columns when a newer one resumes it, and its rows are the uninterrupted run's, cut to them.
TEST(TrainerTest, ARunBegunWithFewerColumnsKeepsThemOnResume) {
  const std::string whole = TempRunDir("columns_whole"), old = TempRunDir("columns_old");
  Trainer::Start(TinyConfig("cem"), whole)->Run();
  CrashAfterRows(TinyConfig("cem"), old, 3);
  const fs::path progress = fs::path(old) / "progress.csv";
  std::vector<std::string> lines;
  {
    std::ifstream in(progress);
    for (std::string line; std::getline(in, line);) lines.push_back(FirstProgressFields(line, 14));
  }
  // Rewrite the log as the older version would have, and its checkpoint's record of it.
  {
    std::ofstream out(progress, std::ios::trunc);
    for (size_t i = 0; i < lines.size(); ++i) {
      out << lines[i] << "\n";
    }
  }
  RewriteCheckpoint(old);

  Trainer::Resume(old)->Run();
  std::vector<std::string> expected = RowsWithoutTimes(whole);
  for (std::string& row : expected) row = FirstProgressFields(row, 12);  // 14 less two clocks
  EXPECT_EQ(RowsWithoutTimes(old), expected);

  // A log of some other kind is refused by name.
  const std::string other = TempRunDir("columns_other");
  {
    std::unique_ptr<Trainer> trainer = Trainer::Start(TinyConfig("cem"), other);
  }
  std::ofstream(fs::path(other) / "progress.csv", std::ios::trunc) << "Epoch,Episode,Reward\n";
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(other); }),
              ::testing::AllOf(::testing::HasSubstr("has the columns 'Epoch,Episode,Reward'"),
                               ::testing::HasSubstr("or its first columns")));
}

TEST(TrainerTest, ResumingBeforeTheFirstCheckpointStartsOver) {
  const std::string dir = TempRunDir("early");
  { std::unique_ptr<Trainer> trainer = Trainer::Start(TinyConfig("random"), dir); }  // no Run
  Trainer::Resume(dir)->Run();
  const std::string reference = TempRunDir("early_reference");
  Trainer::Start(TinyConfig("random"), reference)->Run();
  EXPECT_EQ(RowsWithoutTimes(dir), RowsWithoutTimes(reference));
}

TEST(TrainerTest, RunDirectoriesAreNotMixedUp) {
  const std::string dir = TempRunDir("twice");
  Trainer::Start(TinyConfig("rce"), dir);
  EXPECT_THAT(ErrorMessage([&] { Trainer::Start(TinyConfig("rce"), dir); }),
              ::testing::HasSubstr("already holds a run"));
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(TempRunDir("nothing")); }),
              ::testing::HasSubstr("holds no run"));
}

// A first checkpoint that never completed (a full disk, a kill before it) leaves rows with no
// checkpoint beside its pending mark: the resume drops them, starts again from the beginning,
// writes the rows of an uninterrupted run, and its session says so.
TEST(TrainerTest, ARunWhoseFirstCheckpointNeverCompletedStartsAgainAndSaysSo) {
  const std::string whole = TempRunDir("whole_first");
  {
    auto trainer = Trainer::Start(TinyConfig("cem"), whole);
    EXPECT_TRUE(fs::exists(fs::path(whole) / "checkpoint.pending"));  // until the first one
    trainer->Run();
  }
  EXPECT_FALSE(fs::exists(fs::path(whole) / "checkpoint.pending"));
  const std::string cut = TempRunDir("cut_first");
  fs::copy(whole, cut, fs::copy_options::recursive);
  fs::remove(fs::path(cut) / "lock");
  fs::remove_all(fs::path(cut) / "checkpoint");  // as if it had never been written
  std::ofstream(fs::path(cut) / "checkpoint.pending") << "pending\n";
  Trainer::Resume(cut)->Run();
  EXPECT_EQ(RowsWithoutTimes(cut), RowsWithoutTimes(whole));
  EXPECT_THAT(FileBytes(fs::path(cut) / "sessions.jsonl"),
              ::testing::HasSubstr("its first checkpoint was never completed"));
  EXPECT_FALSE(fs::exists(fs::path(cut) / "checkpoint.pending"));
}

// A run knows its own state: parts that disagree with the checkpoint's manifest are refused,
// naming the file, instead of being used silently.
TEST(TrainerTest, ARunWhosePartsDisagreeIsRefusedByName) {
  const std::string original = TempRunDir("parts");
  Trainer::Start(TinyConfig("cem"), original)->Run();
  const auto copy = [&](const std::string& name) {
    const std::string dir = TempRunDir(name);
    fs::copy(original, dir, fs::copy_options::recursive);
    fs::remove(fs::path(dir) / "lock");
    return fs::path(dir);
  };
  const auto rows = [](const fs::path& dir) {
    std::ifstream in(dir / "progress.csv");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  };
  const auto write_rows = [](const fs::path& dir, const std::vector<std::string>& lines) {
    std::ofstream out(dir / "progress.csv", std::ios::trunc);
    for (const std::string& line : lines) out << line << "\n";
  };
  const size_t n = rows(fs::path(original)).size() - 1;  // rows the last checkpoint covers
  {
    const fs::path dir = copy("no_state");
    fs::remove(dir / "checkpoint" / "state.json");
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("state.json' is missing: the checkpoint's manifest lists it"));
  }
  {
    const fs::path dir = copy("no_checkpoint");
    fs::remove_all(dir / "checkpoint");
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr(fmt::format(
                    "progress.csv' has {} rows but the run has no checkpoint", n)));
  }
  {
    const fs::path dir = copy("no_progress");  // named as missing, not as unreadable
    fs::remove(dir / "progress.csv");
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("progress.csv': it does not exist"));
  }
  {
    const fs::path dir = copy("shortened");
    std::vector<std::string> lines = rows(dir);
    lines.pop_back();
    write_rows(dir, lines);
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr(fmt::format(
                    "progress.csv' has {} rows but the checkpoint covers {}", n - 1, n)));
  }
  {
    const fs::path dir = copy("edited");
    std::vector<std::string> lines = rows(dir);
    lines[2][0] = '7';  // the second row's epoch
    write_rows(dir, lines);
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr(
                    fmt::format("progress.csv' differs in its first {} rows", n)));
  }
  {
    const fs::path dir = copy("garbage_state");
    std::ofstream(dir / "checkpoint" / "state.json") << "{ garbage";
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("state.json' differs from the file the checkpoint wrote"));
  }
  {
    const fs::path dir = copy("garbage_model");
    std::ofstream(dir / "checkpoint" / "ensemble.pt", std::ios::trunc) << "not a model";
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("ensemble.pt' differs from the file the checkpoint wrote"));
  }
  {
    const fs::path dir = copy("edited_config");
    std::ofstream(dir / "config.yaml", std::ios::app) << "# a comment changes the bytes\n";
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("config.yaml' differs from the configuration the run's "
                                     "checkpoint recorded: it was edited"));
  }
  {
    const fs::path dir = copy("edited_manifest");
    const fs::path manifest = dir / "checkpoint" / "manifest.json";
    std::stringstream text;
    text << std::ifstream(manifest).rdbuf();
    std::string edited = text.str();
    const size_t at = edited.find(fmt::format("\"rows\": {}", n));
    ASSERT_NE(at, std::string::npos);
    edited.replace(at, fmt::format("\"rows\": {}", n).size(), fmt::format("\"rows\": {}", n - 1));
    std::ofstream(manifest, std::ios::trunc) << edited;
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("manifest.json' is damaged: its checksum does not match "
                                     "its content: it was edited"));
  }
  {
    const fs::path dir = copy("no_manifest");
    fs::remove(dir / "checkpoint" / "manifest.json");
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("manifest.json' is missing: the checkpoint was written by "
                                     "a version that writes one"));
  }
  {
    const fs::path dir = copy("no_sessions");
    fs::remove(dir / "sessions.jsonl");
    EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(dir.string()); }),
                ::testing::HasSubstr("sessions.jsonl' is missing: the run's checkpoint covers "
                                     "its first 1 session(s)"));
  }
  // The untouched copy resumes (nothing left to do: its budget is spent).
  EXPECT_NO_THROW(Trainer::Resume(copy("untouched").string())->Run());
}

// A resume given a new budget changes config.yaml and the manifest that records it together; a
// stop between the two is finished by the next resume and named by readers meanwhile.
TEST(TrainerTest, ABudgetChangeKeepsTheConfigCoveredEvenWhenInterrupted) {
  const std::string dir = TempRunDir("rebudget");
  TrainConfig config = TinyConfig("cem");
  const std::int64_t first_budget = config.training.total_steps;
  Trainer::Start(config, dir)->Run();
  const std::string before = [&] {
    std::stringstream text;
    text << std::ifstream(fs::path(dir) / "config.yaml").rdbuf();
    return text.str();
  }();
  Trainer::Resume(dir, first_budget + 300);  // changes the budget, then stops before any step
  EXPECT_NO_THROW(VerifiedCheckpoint(RunDirectory(dir)));
  // A stop after the new manifest went in but before config.yaml did.
  fs::rename(fs::path(dir) / "config.yaml", fs::path(dir) / "config.yaml.tmp");
  std::ofstream(fs::path(dir) / "config.yaml") << before;
  EXPECT_THAT(ErrorMessage([&] { VerifiedCheckpoint(RunDirectory(dir)); }),
              ::testing::HasSubstr("a budget change was interrupted: resume the run to finish"));
  const std::unique_ptr<Trainer> resumed = Trainer::Resume(dir);
  EXPECT_EQ(resumed->config().training.total_steps, first_budget + 300);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "config.yaml.tmp"));
  resumed->Run();
  EXPECT_GE(resumed->steps_done(), first_budget + 300);
}

// A model-free learner behind the same run machinery: rows per epoch, and a resume after a
// crash between a row and its checkpoint gives an uninterrupted run's rows.
TrainConfig TinyModelFree(const std::string& algorithm) {
  return ParseTrainConfig(fmt::format(R"(
task: PointGoal1
variant: paper-lidar
algorithm: {}
seed: 4
training: {{total_steps: 900}}
policy_optimisation: {{steps_per_epoch: 300, policy_hidden: [16], value_hidden: [16],
                      value_iterations: 5}}
)",
                                      algorithm),
                          "tiny model-free");
}

// A model-free session's wall time splits into the rollouts, the updates, the value fits and the
// checkpoints, each measured; the epoch's own split (for benchmarks) lies inside it.
TEST(TrainerTest, AModelFreeSessionsTimeIsSplitIntoItsParts) {
  std::unique_ptr<Trainer> trainer =
      Trainer::Start(TinyModelFree("trpo-lagrangian"), TempRunDir("mf_split"));
  trainer->Run();
  std::vector<std::string> parts;
  for (const auto& [part, seconds] : trainer->TimeSplit()) {
    parts.push_back(part);
    if (part != "other") {
      EXPECT_GT(seconds, 0.0) << part;
    }
  }
  EXPECT_EQ(parts, (std::vector<std::string>{"rollout", "policy_updates", "value_fits",
                                             "checkpoints", "other"}));
  const auto& learner = dynamic_cast<const PolicyOptLearner&>(trainer->learner());
  EXPECT_GT(learner.last_timings().rollout, 0.0);
  EXPECT_LT(learner.last_timings().rollout, trainer->TimeSplit()[0].second);
}

TEST(TrainerTest, ModelFreeLearnersResumeToTheSameRows) {
  for (const std::string algorithm : {"trpo", "trpo-lagrangian", "cpo", "ppo-lagrangian"}) {
    SCOPED_TRACE(algorithm);
    const std::string whole = TempRunDir("mf_whole_" + algorithm);
    const std::string crashed = TempRunDir("mf_crashed_" + algorithm);
    Trainer::Start(TinyModelFree(algorithm), whole)->Run();
    const std::vector<std::string> rows = RowsWithoutTimes(whole);
    ASSERT_EQ(rows.size(), 4u);  // header and three epochs of 300 steps
    EXPECT_EQ(rows[0].rfind("Epoch,AverageEpRet,AverageEpCost,EpLen", 0), 0u);
    struct Crash {};
    try {
      int units = 0;
      Trainer::Start(TinyModelFree(algorithm), crashed)->Run([&](const ProgressSummary&) {
        if (++units == 2) throw Crash{};
      });
      FAIL() << "expected the simulated crash";
    } catch (const Crash&) {
    }
    Trainer::Resume(crashed)->Run();
    EXPECT_EQ(RowsWithoutTimes(crashed), rows);
    // The networks, their optimisers' moments and the generator, byte for byte: the moments
    // are keyed by place, not by the tensors' addresses, which differ between the two runs.
    const auto bytes = [](const std::string& run) {
      return FileBytes(fs::path(run) / "checkpoint" / "networks.pt");
    };
    EXPECT_FALSE(bytes(whole).empty());
    EXPECT_TRUE(bytes(crashed) == bytes(whole)) << "networks.pt differs";
  }
}

// Several environments stepped side by side (on threads) give the same rows every time, and
// resume to them.
TEST(TrainerTest, ModelFreeRowsWithSeveralEnvironmentsDoNotDependOnThreads) {
  TrainConfig config = TinyModelFree("trpo-lagrangian");
  config.policy_optimisation.envs = 3;
  config.policy_optimisation.env_threads = 3;
  const std::string a = TempRunDir("mf_envs_a"), b = TempRunDir("mf_envs_b");
  Trainer::Start(config, a)->Run();
  struct Crash {};
  try {
    Trainer::Start(config, b)->Run([](const ProgressSummary& unit) {
      if (unit.epoch == 2) throw Crash{};
    });
  } catch (const Crash&) {
  }
  Trainer::Resume(b)->Run();
  EXPECT_EQ(RowsWithoutTimes(a), RowsWithoutTimes(b));
  EXPECT_EQ(RowsWithoutTimes(a).size(), 4u);
  config.policy_optimisation.envs = 7;  // 300 steps cannot be shared by 7
  EXPECT_THAT(ErrorMessage([&] { Trainer::Start(config, TempRunDir("mf_envs_bad")); }),
              ::testing::HasSubstr("steps_per_epoch is 300 and envs 7"));
}

// A stop in the middle of a model-free epoch pauses it after the rollout's round or the value
// fits' iteration under way, with a checkpoint that holds the epoch; the resume carries it on to
// the uninterrupted run's rows, with one environment or several.
TEST(TrainerTest, AModelFreeEpochStoppedInItsRolloutOrValueFitsResumesToTheSameRows) {
  for (const int envs : {1, 3}) {
    for (const std::string algorithm : {"trpo-lagrangian", "ppo-lagrangian"}) {
      SCOPED_TRACE(::testing::Message() << algorithm << " " << envs);
      TrainConfig config = TinyModelFree(algorithm);
      config.policy_optimisation.envs = config.policy_optimisation.env_threads = envs;
      const std::string whole = TempRunDir("mf_open_whole"), stopped = TempRunDir("mf_open");
      Trainer::Start(config, whole)->Run();
      const fs::path checkpoint = fs::path(stopped) / "checkpoint";
      const auto open_epoch = [&] {
        return nlohmann::json::parse(std::ifstream(checkpoint / "epoch.json"));
      };
      // Half way through the second epoch's rollout.
      EXPECT_EQ(StopAt(Trainer::Start(config, stopped), 450), 450);
      EXPECT_EQ(RowsWithoutTimes(stopped).size(), 2u);  // header and the first epoch
      EXPECT_EQ(open_epoch().at("updated"), false);
      EXPECT_EQ(open_epoch().at("rounds"), 150 / envs);
      EXPECT_EQ(nlohmann::json::parse(std::ifstream(checkpoint / "manifest.json")).at("steps_done"),
                450);
      {
        // Then, resumed, after the second of its 5 value-fit iterations (the stop is asked after
        // each but the last, once the rollout's 600 steps are done).
        std::unique_ptr<Trainer> resumed = Trainer::Resume(stopped);
        EXPECT_EQ(resumed->steps_done(), 450);
        int asked = 0;
        RunOptions options;
        options.checkpoint_seconds = 1e9;
        options.stop_requested = [&] { return resumed->steps_done() == 600 && ++asked == 2; };
        resumed->Run(options);
        EXPECT_FALSE(resumed->learner().Finished());
      }
      EXPECT_EQ(RowsWithoutTimes(stopped).size(), 2u);
      EXPECT_EQ(open_epoch().at("updated"), true);
      EXPECT_EQ(open_epoch().at("fitted"), 2);
      Trainer::Resume(stopped)->Run();
      EXPECT_EQ(RowsWithoutTimes(stopped), RowsWithoutTimes(whole));
      EXPECT_FALSE(fs::exists(checkpoint / "epoch.json"));  // the last checkpoint ends an epoch
    }
  }
}

TEST(TrainerTest, ACheckpointOfAnOpenModelFreeEpochIsCheckedWhenRead) {
  const std::string dir = TempRunDir("mf_open_damaged");
  TrainConfig config = TinyModelFree("cpo");
  config.policy_optimisation.envs = config.policy_optimisation.env_threads = 2;
  StopAt(Trainer::Start(config, dir), 450);
  const KeptCheckpoint kept(dir, "mf_open_damaged_saved");
  const fs::path& checkpoint = kept.path;
  const fs::path& saved = kept.saved;
  const auto resume_error = [&] {
    RewriteCheckpoint(dir);
    return ErrorMessage([&] { Trainer::Resume(dir); });
  };
  WriteFile(checkpoint / "epoch.pt", "not an archive");
  EXPECT_THAT(resume_error(), ::testing::HasSubstr("could not read the epoch under way from"));
  kept.Restore();
  // epoch.pt with one tensor replaced: a damaged environment state, then actions of another
  // length.
  const auto replace = [&](const std::string& key, const torch::Tensor& value) {
    torch::serialize::InputArchive in;
    in.load_from((saved / "epoch.pt").string());
    torch::serialize::OutputArchive out;
    for (const std::string& name : in.keys()) {
      torch::Tensor tensor;
      in.read(name, tensor);
      out.write(name, name == key ? value : tensor);
    }
    SaveArchive(out, (checkpoint / "epoch.pt").string());
  };
  replace("env_state1", torch::zeros({5}, torch::kUInt8));
  EXPECT_THAT(resume_error(), ::testing::AllOf(::testing::HasSubstr("epoch.pt' is damaged"),
                                               ::testing::HasSubstr("environment state")));
  kept.Restore();
  replace("actions0", torch::zeros({3}));
  EXPECT_THAT(resume_error(), ::testing::HasSubstr("actions0 is missing or not 150 Float values"));
  kept.Restore();
  WriteFile(checkpoint / "epoch.json", R"({"updated": false, "steps": 300, "rounds": 0})");
  EXPECT_THAT(resume_error(), ::testing::AllOf(::testing::HasSubstr("epoch.json' is damaged"),
                                               ::testing::HasSubstr("step_cost")));
  kept.Restore();
  WriteFile(checkpoint / "epoch.json", R"({"updated": false, "steps": 300, "rounds": 150,
                                            "step_cost": "0", "needs_reset": [0, 0]})");
  EXPECT_THAT(resume_error(), ::testing::HasSubstr("an epoch of 300 steps at round 150, with 2 "
                                                   "reset flags: expected 1 to 300 steps"));
  kept.Restore();
  WriteFile(checkpoint / "epoch.json", R"({"updated": false, "steps": 300, "rounds": 10,
                                            "step_cost": "0", "needs_reset": [0, 0]})");
  EXPECT_THAT(resume_error(), ::testing::HasSubstr("environment 0 took 75 steps in 10 rounds"));
  kept.Restore();
  EXPECT_NO_THROW(Trainer::Resume(dir)->Run());
}

// A finished run continued to a larger budget writes the rows a run started with that budget
// writes, and its config.yaml then holds the new budget.
TEST(TrainerTest, AFinishedRunContinuesToALargerBudget) {
  TrainConfig longer = TinyConfig("cem");
  longer.training.total_steps = 600;
  const std::string whole = TempRunDir("budget_whole"), extended = TempRunDir("budget_extended");
  Trainer::Start(longer, whole)->Run();
  Trainer::Start(TinyConfig("cem"), extended)->Run();  // 400 steps
  ASSERT_LT(RowsWithoutTimes(extended).size(), RowsWithoutTimes(whole).size());
  // Its last episode ended an epoch: the refit it would have had is put off, not done.
  std::ifstream state(fs::path(extended) / "checkpoint" / "state.json");
  EXPECT_EQ(nlohmann::json::parse(state).at("models_due"), true);
  Trainer::Resume(extended, 600)->Run();
  EXPECT_EQ(RowsWithoutTimes(extended), RowsWithoutTimes(whole));
  EXPECT_EQ(LoadTrainConfig((fs::path(extended) / "config.yaml").string()).training.total_steps,
            600);
  // Nothing left below what is done.
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(extended, 300); }),
              ::testing::HasSubstr("to 300 steps: it has done"));
  EXPECT_EQ(LoadTrainConfig((fs::path(extended) / "config.yaml").string()).training.total_steps,
            600);
}

// A model-free run whose last epoch the old budget cut short cannot become the longer run; one
// that ended on an epoch's end can.
TEST(TrainerTest, AModelFreeRunContinuesOnlyFromAWholeEpoch) {
  const std::string whole = TempRunDir("mf_budget_whole"), cut = TempRunDir("mf_budget_cut");
  const std::string exact = TempRunDir("mf_budget_exact");
  Trainer::Start(TinyModelFree("cpo"), whole)->Run();  // 900 steps: three epochs
  TrainConfig shorter = TinyModelFree("cpo");
  shorter.training.total_steps = 450;  // one epoch and a half
  Trainer::Start(shorter, cut)->Run();
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(cut, 900); }),
              ::testing::HasSubstr("last epoch was cut to 150 of its 300 steps"));
  shorter.training.total_steps = 600;
  Trainer::Start(shorter, exact)->Run();
  Trainer::Resume(exact, 900)->Run();
  EXPECT_EQ(RowsWithoutTimes(exact), RowsWithoutTimes(whole));
  // Stopped in the rollout of an epoch: one the old budget cut cannot become whole; a whole one
  // goes on under the new budget.
  const std::string open_cut = TempRunDir("mf_budget_open_cut");
  shorter.training.total_steps = 450;
  StopAt(Trainer::Start(shorter, open_cut), 400);
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(open_cut, 900); }),
              ::testing::HasSubstr("last epoch was cut to 150 of its 300 steps"));
  const std::string open_whole = TempRunDir("mf_budget_open_whole");
  shorter.training.total_steps = 600;
  StopAt(Trainer::Start(shorter, open_whole), 400);
  Trainer::Resume(open_whole, 900)->Run();
  EXPECT_EQ(RowsWithoutTimes(open_whole), RowsWithoutTimes(whole));
  // Stopped in the second epoch's value fits, its 600 steps taken: a budget of 600 ends it.
  const std::string in_fits = TempRunDir("mf_budget_in_fits");
  {
    std::unique_ptr<Trainer> trainer = Trainer::Start(TinyModelFree("cpo"), in_fits);
    RunOptions options;
    options.stop_requested = [&] { return trainer->steps_done() == 600; };
    trainer->Run(options);
  }
  EXPECT_EQ(RowsWithoutTimes(in_fits).size(), 2u);
  Trainer::Resume(in_fits, 600)->Run();
  std::vector<std::string> two_epochs = RowsWithoutTimes(whole);
  two_epochs.pop_back();
  EXPECT_EQ(RowsWithoutTimes(in_fits), two_epochs);
  EXPECT_THAT(ErrorMessage([&] { Trainer::Resume(in_fits, 500); }),
              ::testing::HasSubstr("to 500 steps: it has done 600 already"));
}

TEST(TrainerTest, ARunDirectoryServesOneProcessAtATime) {
  const std::string dir = TempRunDir("locked");
  const std::unique_ptr<Trainer> first = Trainer::Start(TinyConfig("rce"), dir);
  EXPECT_THAT(testing::ErrorMessage([&] { Trainer::Resume(dir); }),
              ::testing::HasSubstr("is in use by another cmbrl process (pid "));
}

// Deleting the lock file does not free a live run: the run's directory is locked too.
TEST(TrainerTest, ALockFileDeletedUnderALiveRunStillKeepsOthersOut) {
  const std::string dir = TempRunDir("lock-deleted");
  const std::unique_ptr<Trainer> first = Trainer::Start(TinyConfig("rce"), dir);
  ASSERT_TRUE(fs::remove(fs::path(dir) / "lock"));
  EXPECT_THAT(testing::ErrorMessage([&] { Trainer::Resume(dir); }),
              ::testing::HasSubstr("is in use by another cmbrl process"));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "lock"));  // the refused process touched nothing
}

// A lock whose holder has ended is free, with no file to delete first.
TEST(TrainerTest, ALockWhoseHolderEndedIsFree) {
  const std::string dir = TempRunDir("lock-ended");
  Trainer::Start(TinyConfig("rce"), dir).reset();
  ASSERT_TRUE(fs::exists(fs::path(dir) / "lock"));
  EXPECT_NO_THROW(Trainer::Resume(dir));
}

}  // namespace
}  // namespace cmbrl

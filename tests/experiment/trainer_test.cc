#include "cmbrl/experiment/trainer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cmbrl/models/labeled_state_buffer.h"
#include "cmbrl/models/transition_buffer.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using testing::ErrorMessage;

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

std::string TempRunDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("trainer_test_" + name);
  fs::remove_all(dir);
  return dir.string();
}

// progress.csv without the Time and MsPerPlan columns (wall-clock figures).
std::vector<std::string> RowsWithoutTimes(const std::string& run_dir) {
  std::ifstream in(fs::path(run_dir) / "progress.csv");
  std::vector<std::string> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    for (int column = 0; std::getline(stream, cell, ','); ++column) {
      if (column != 6 && column != 11) cells.push_back(cell);
    }
    rows.push_back(fmt::format("{}", fmt::join(cells, ",")));
  }
  return rows;
}

TEST(TrainerTest, AShortRunWritesEveryFile) {
  const std::string dir = TempRunDir("files");
  std::vector<ProgressRow> seen;
  Trainer::Start(TinyConfig("rce"), dir)->Run([&](const ProgressRow& row) { seen.push_back(row); });
  EXPECT_TRUE(fs::exists(fs::path(dir) / "config.yaml"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "state.json"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "ensemble.pt"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "classifier.json"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "checkpoint" / "transitions.bin"));
  // 400 agent steps of whole episodes of about 100: four or five rows, one per episode.
  const std::vector<std::string> rows = RowsWithoutTimes(dir);
  ASSERT_GE(seen.size(), 4u);
  EXPECT_EQ(rows.size(), seen.size() + 1);
  EXPECT_EQ(rows[0],
            "Epoch,Episode,EpRet,EpCost,TotalEnvInteracts,PretrainInteracts,DynamicsValMSE,"
            "ClassifierSafeAcc,ClassifierUnsafeAcc,FeasibleFraction,Steps,GoalsMet");
  EXPECT_GE(seen.back().total_env_interacts, 400);
  EXPECT_EQ(seen[0].epoch, 1);
  EXPECT_EQ(seen[2].epoch, 2);  // two episodes per epoch
  EXPECT_GT(seen[0].pretrain_interacts, 0);
  EXPECT_EQ(seen[0].pretrain_interacts, seen.back().pretrain_interacts);
  EXPECT_TRUE(std::isfinite(seen[0].dynamics_validation_mse));
  EXPECT_GT(seen[0].ms_per_plan, 0.0);
  // The resolved config reads back as the same config.
  EXPECT_EQ(TrainConfigToYaml(LoadTrainConfig((fs::path(dir) / "config.yaml").string())),
            TrainConfigToYaml(TinyConfig("rce")));
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

TEST(TrainerTest, ResumingAfterACrashGivesTheSameRows) {
  const std::string whole = TempRunDir("whole"), crashed = TempRunDir("crashed");
  Trainer::Start(TinyConfig("rce"), whole)->Run();
  // Stop after the third row is written but before its checkpoint: the worst moment.
  struct Crash {};
  try {
    Trainer::Start(TinyConfig("rce"), crashed)->Run([](const ProgressRow& row) {
      if (row.episode == 3) throw Crash{};
    });
    FAIL() << "expected the simulated crash";
  } catch (const Crash&) {
  }
  EXPECT_EQ(RowsWithoutTimes(crashed).size(), 4u);  // header + 3 rows, the third uncovered
  Trainer::Resume(crashed)->Run();
  EXPECT_EQ(RowsWithoutTimes(crashed), RowsWithoutTimes(whole));
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

TEST(TrainerTest, ARunDirectoryServesOneProcessAtATime) {
  const std::string dir = TempRunDir("locked");
  const std::unique_ptr<Trainer> first = Trainer::Start(TinyConfig("rce"), dir);
  EXPECT_THAT(testing::ErrorMessage([&] { Trainer::Resume(dir); }),
              ::testing::HasSubstr("is in use by another cmbrl process"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/sweep/experiment.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "cmbrl/report/reference.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ErrorMessage;

// An experiment folder of the test's own, two folders below a copy-free configs/ link: the
// experiment finds the repository's presets through `configs_dir`.
fs::path WriteExperiment(const std::string& name, const std::string& yaml) {
  const fs::path dir = fs::path(testing::TestTempPath("experiments")) / name;
  fs::create_directories(dir);
  std::ofstream(dir / kExperimentFile) << yaml;
  return dir;
}

const char* kConfigs = CMBRL_SOURCE_DIR "/configs";

// Every (task, method) config of the CPU grid resolves, and within a task the three methods
// agree on every key but the method: one protocol for every cell.
TEST(ExperimentTest, TheCpuGridsCellsShareEverySettingWithinATask) {
  const Experiment grid = LoadExperiment(CMBRL_SOURCE_DIR "/experiments/cpu-grid");
  EXPECT_EQ(grid.name, "cpu-grid");
  EXPECT_EQ(grid.window, 3000);
  EXPECT_EQ(grid.seeds, (std::vector<std::uint64_t>{0, 1, 2, 3, 4}));
  const auto runs = ResolveExperimentRuns(grid);
  ASSERT_EQ(runs.size(), 60u);  // 4 tasks x 3 methods x 5 seeds
  std::map<std::string, std::string> per_task;
  for (const auto& [run, config] : runs) {
    SCOPED_TRACE(run.name);
    EXPECT_EQ(config.seed, run.seed);
    EXPECT_EQ(config.training.total_steps, grid.window);
    EXPECT_DOUBLE_EQ(config.classifier.threshold, 0.5);  // the original code's
    EXPECT_FALSE(config.ensemble.predict_delta);          // the absolute state, both robots
    TrainConfig normalised = config;
    normalised.planner = "rce";
    normalised.seed = 0;
    const std::string text = TrainConfigToYaml(normalised);
    const auto [it, first] = per_task.emplace(config.task, text);
    EXPECT_EQ(text, it->second) << "differs from the task's first method";
  }
  EXPECT_EQ(per_task.size(), 4u);
}

// Every experiment of the repository loads and resolves every run's config.
TEST(ExperimentTest, EveryDeclaredExperimentResolves) {
  int experiments = 0;
  for (const auto& entry : fs::directory_iterator(CMBRL_SOURCE_DIR "/experiments")) {
    if (!IsExperimentDir(entry.path())) continue;
    SCOPED_TRACE(entry.path().string());
    const Experiment e = LoadExperiment(entry.path());
    EXPECT_FALSE(ResolveExperimentRuns(e).empty());
    ++experiments;
  }
  EXPECT_GE(experiments, 5);  // cpu-grid, model-free, bf16-planning, random-samples,
                              // rce-population
}

// Every experiment's README is short and opens with its table: at most 100 lines, and a table
// before its first section heading.
TEST(ExperimentTest, EveryReadmeIsShortAndOpensWithItsTable) {
  for (const auto& entry : fs::directory_iterator(CMBRL_SOURCE_DIR "/experiments")) {
    if (!IsExperimentDir(entry.path())) continue;
    SCOPED_TRACE(entry.path().string());
    std::ifstream readme(entry.path() / "README.md");
    ASSERT_TRUE(readme.good()) << "no README.md";
    int lines = 0, table_line = 0, first_section = 0;
    for (std::string line; std::getline(readme, line);) {
      ++lines;
      if (table_line == 0 && line.rfind("|---", 0) == 0) table_line = lines;
      if (first_section == 0 && line.rfind("## ", 0) == 0) first_section = lines;
    }
    EXPECT_LE(lines, 100);
    EXPECT_GT(table_line, 0) << "no table";
    if (first_section > 0) {
      EXPECT_LT(table_line, first_section) << "the table comes after a section";
    }
  }
}

TEST(ExperimentTest, AxesAndOverridesApplyToEveryRun) {
  const fs::path dir = WriteExperiment("axes",
                                       "family: cpu\ntasks: [PointGoal2]\nmethods: [rce, cem]\n"
                                       "seeds: [0, 1]\nwindow: 2000\n"
                                       "set: {training.total_steps: 2000}\n"
                                       "axes: {classifier.threshold: [0.3, 0.5]}\n");
  const Experiment e = LoadExperiment(dir, kConfigs);
  EXPECT_EQ(e.sha256.size(), 64u);
  const auto runs = ResolveExperimentRuns(e);
  ASSERT_EQ(runs.size(), 8u);
  EXPECT_EQ(runs[0].first.name, "pointgoal2-rce-threshold=0.3-s0");
  EXPECT_DOUBLE_EQ(runs[0].second.classifier.threshold, 0.3);
  EXPECT_DOUBLE_EQ(runs[2].second.classifier.threshold, 0.5);
  EXPECT_EQ(runs[0].second.training.total_steps, 2000);
  EXPECT_EQ(runs[0].second.planning.cross_entropy.population, 100);  // the cpu family
  EXPECT_EQ(ExperimentGrid(e).overlays, (std::vector<std::string>{std::string(kConfigs) +
                                                                  "/cpu.yaml"}));
  EXPECT_EQ(e.runs_dir(), dir / "runs");
}

// The report compares each setting against the first one the file declares, not the first in
// natural order: a study declared [fp32, bf16] reads bf16 - fp32.
TEST(ExperimentTest, TheStampListsTheSettingsInTheOrderDeclared) {
  const fs::path dir = WriteExperiment("order",
                                       "family: cpu\ntasks: [PointGoal1, PointGoal2]\n"
                                       "methods: [rce, cem]\nseeds: [0, 1]\nwindow: 2000\n"
                                       "axes: {ensemble.precision: [fp32, bf16], "
                                       "planning.horizon: [8, 5]}\n");
  const ExperimentStamp stamp = StampOf(LoadExperiment(dir, kConfigs));
  EXPECT_EQ(stamp.settings,
            (std::vector<std::string>{"precision=fp32-horizon=8", "precision=fp32-horizon=5",
                                      "precision=bf16-horizon=8", "precision=bf16-horizon=5"}));
  EXPECT_EQ(stamp.name, "order");
  const ExperimentStamp plain =
      StampOf(LoadExperiment(WriteExperiment("plain",
                                             "family: cpu\ntasks: [PointGoal1]\nmethods: [rce]\n"
                                             "seeds: [0]\nwindow: 2000\n"),
                             kConfigs));
  EXPECT_EQ(plain.settings, (std::vector<std::string>{""}));
}

TEST(ExperimentTest, BadDeclarationsNameTheKeyAndTheValue) {
  const std::string ok = "tasks: [PointGoal1]\nmethods: [rce]\nseeds: [0]\nwindow: 3000\n";
  const auto error = [&](const std::string& yaml) {
    return ErrorMessage([&] { LoadExperiment(WriteExperiment("bad", yaml), kConfigs); });
  };
  EXPECT_THAT(error("family: paper\n" + ok + "seed: 3\n"), HasSubstr("unknown key 'seed'"));
  EXPECT_THAT(error(ok), HasSubstr("key 'family' is missing"));
  EXPECT_THAT(error("family: gpu\n" + ok), HasSubstr("key 'family' is 'gpu'"));
  EXPECT_THAT(error("family: paper\ntasks: [AntGoal1]\nmethods: [rce]\nseeds: [0]\nwindow: 9\n"),
              HasSubstr("key 'tasks' holds 'AntGoal1'"));
  EXPECT_THAT(error("family: paper\ntasks: [PointGoal1]\nmethods: [mppi]\nseeds: [0]\nwindow: 9\n"),
              HasSubstr("key 'methods' holds 'mppi'"));
  EXPECT_THAT(error("family: paper\ntasks: [PointGoal1]\nmethods: [rce]\nseeds: [1, 1]\nwindow: 9\n"),
              HasSubstr("repeats a seed"));
  EXPECT_THAT(error("family: paper\ntasks: [PointGoal1]\nmethods: [rce]\nseeds: [0]\nwindow: -4\n"),
              HasSubstr("key 'window' is -4"));
  EXPECT_THAT(error("family: paper\ntasks: [PointGoal1]\nmethods: [rce]\nseeds: []\nwindow: 9\n"),
              HasSubstr("key 'seeds' is '[]': expected a non-empty list"));
  EXPECT_THAT(error("family: paper\n" + ok + "axes: {classifier.treshold: [0.3]}\n"),
              HasSubstr("unknown key 'classifier.treshold'"));
  EXPECT_THAT(error("family: paper\n" + ok + "axes: {classifier.threshold: [2.5]}\n"),
              HasSubstr("threshold"));
  EXPECT_THAT(error("family: paper\n" + ok + "set: [planning.population=3]\n"),
              HasSubstr("key 'set'"));
  EXPECT_THAT(ErrorMessage([&] { LoadExperiment("/nonexistent", kConfigs); }),
              HasSubstr("is not an experiment"));
  const std::string declared = "family: paper\n" + ok;
  EXPECT_THAT(error(declared + "decision: equivalence\n"),
              HasSubstr("key 'decision' is 'equivalence': expected a mapping"));
  EXPECT_THAT(error(declared + "decision: {rule: smaller}\n"),
              HasSubstr("key 'decision.rule' is 'smaller': expected 'equivalence' or "
                        "'difference'"));
  EXPECT_THAT(error(declared + "decision: {band: 0.2}\n"),
              HasSubstr("key 'decision.rule' is missing"));
  EXPECT_THAT(error(declared + "decision: {rule: equivalence}\n"),
              HasSubstr("key 'decision.band' is missing: expected a share"));
  EXPECT_THAT(error(declared + "decision: {rule: equivalence, band: 20}\n"),
              HasSubstr("key 'decision.band' is '20': expected a share of the first setting's "
                        "mean in (0, 1]"));
  EXPECT_THAT(error(declared + "decision: {rule: equivalence, band: wide}\n"),
              HasSubstr("key 'decision.band' is 'wide'"));
  EXPECT_THAT(error(declared + "decision: {rule: equivalence, band: .nan}\n"),
              HasSubstr("key 'decision.band' is '.nan'"));
  EXPECT_THAT(error(declared + "decision: {rule: difference, band: 0.2}\n"),
              HasSubstr("key 'decision.band' is '0.2': expected none with 'rule: difference'"));
  EXPECT_THAT(error(declared + "decision: {rule: difference, level: 0.9}\n"),
              HasSubstr("key 'decision.level' is unknown"));
}

// A declared decision rule reaches the report's stamp; none is declared unless written.
TEST(ExperimentTest, TheDecisionRuleIsDeclaredWithTheExperiment) {
  const std::string base =
      "family: cpu\ntasks: [PointGoal1]\nmethods: [rce]\nseeds: [0]\n"
      "window: 2000\naxes: {ensemble.precision: [fp32, bf16]}\n";
  const Experiment equivalence = LoadExperiment(
      WriteExperiment("equivalence", base + "decision: {rule: equivalence, band: 0.25}\n"),
      kConfigs);
  ASSERT_TRUE(equivalence.decision.has_value());
  EXPECT_EQ(equivalence.decision->kind, DecisionRule::Kind::kEquivalence);
  EXPECT_DOUBLE_EQ(equivalence.decision->band, 0.25);
  const ExperimentStamp stamp = StampOf(equivalence);
  ASSERT_TRUE(stamp.decision.has_value());
  EXPECT_DOUBLE_EQ(stamp.decision->band, 0.25);
  const Experiment difference = LoadExperiment(
      WriteExperiment("difference", base + "decision: {rule: difference}\n"), kConfigs);
  EXPECT_EQ(difference.decision->kind, DecisionRule::Kind::kDifference);
  EXPECT_FALSE(LoadExperiment(WriteExperiment("none", base), kConfigs).decision.has_value());
}

// An experiment of one's own outside a checkout's experiments/ (no configs/ two folders above)
// takes the presets of the source tree the program was built from.
TEST(ExperimentTest, AnExperimentAnywhereFindsThePresets) {
  const fs::path dir = fs::path(testing::TestTempPath("anywhere")) / "deep" / "mine";
  fs::create_directories(dir);
  std::ofstream(dir / kExperimentFile)
      << "family: cpu\ntasks: [PointButton1]\nmethods: [rce]\nseeds: [0]\nwindow: 3000\n";
  ASSERT_FALSE(fs::exists(dir.parent_path().parent_path() / "configs"));
  const Experiment experiment = LoadExperiment(dir);
  EXPECT_EQ(experiment.configs_dir, fs::path(DefaultConfigsDir()));
  EXPECT_TRUE(fs::is_regular_file(experiment.family_file()));
}

TEST(ExperimentTest, TheHashIsTheFilesSha256) {
  const fs::path dir = WriteExperiment("hash", "abc");
  // sha256sum of the three bytes "abc" (FIPS 180-2's first example).
  EXPECT_EQ(Sha256OfFile(dir / kExperimentFile),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace cmbrl

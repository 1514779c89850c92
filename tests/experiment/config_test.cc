#include "cmbrl/experiment/config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>

#include "cmbrl/env/registry.h"
#include "cmbrl/env/tasks/goal_spec.h"
#include "tests/error_message.h"

namespace cmbrl {
namespace {

using testing::ErrorMessage;

TEST(ConfigTest, AnEmptyFileGivesThePapersSettings) {
  const TrainConfig config = ParseTrainConfig("{}", "empty");
  EXPECT_EQ(config.task, "PointGoal1");
  EXPECT_EQ(config.planner, "rce");
  EXPECT_EQ(config.ensemble.hidden_sizes, std::vector<int>({1024, 1024, 1024}));
  EXPECT_EQ(config.planning.cross_entropy.population, 500);
  EXPECT_EQ(config.planning.random.samples, 5000);
  EXPECT_EQ(config.classifier.rounds, 400);
  EXPECT_EQ(config.training.pretrain_episodes, 1000);
  // The original's code as it ran (facts B2, B4): labels beside stored transitions, safe states
  // in storage order, both goal bonuses below 0.2.
  EXPECT_FALSE(config.training.label_every_step);
  EXPECT_EQ(config.classifier.safe_selection, "storage_order");
  EXPECT_TRUE(config.objective.at_goal_test_after_near_bonus);
}

TEST(ConfigTest, EveryYamlFileUnderConfigsLoads) {
  int files = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(CMBRL_SOURCE_DIR "/configs")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(LoadTrainConfig(entry.path().string()));
    ++files;
  }
  EXPECT_GT(files, 14);
}

TEST(ConfigTest, KeysReachTheirComponents) {
  const TrainConfig config = ParseTrainConfig(R"(
task: CarGoal2
planner: cem
seed: 7
ensemble: {ensemble_size: 5, hidden_sizes: [64, 32], batch_size: 128}
classifier: {rounds: 50, threshold: 0.3}
planning: {horizon: 5, population: 100, elites: 10, penalty: 200, random_samples: 300}
training: {pretrain_episodes: 20, total_steps: 2000}
objective: {beta: 0.5}
)",
                                              "inline");
  EXPECT_EQ(config.task, "CarGoal2");
  EXPECT_EQ(config.seed, 7u);
  EXPECT_EQ(config.ensemble.ensemble_size, 5);
  EXPECT_EQ(config.ensemble.hidden_sizes, std::vector<int>({64, 32}));
  EXPECT_EQ(config.classifier.rounds, 50);
  EXPECT_DOUBLE_EQ(config.classifier.threshold, 0.3);
  EXPECT_EQ(config.planning.problem.horizon, 5);
  EXPECT_EQ(config.planning.cross_entropy.elites, 10);
  EXPECT_DOUBLE_EQ(config.planning.penalty, 200);  // one penalty for CEM and random
  EXPECT_EQ(config.planning.random.samples, 300);
  EXPECT_EQ(config.training.total_steps, 2000);
  EXPECT_DOUBLE_EQ(config.objective.beta, 0.5);
}

TEST(ConfigTest, WrittenConfigReadsBackTheSame) {
  TrainConfig config = ParseTrainConfig("planner: random\nensemble: {hidden_sizes: [8]}", "a");
  const std::string yaml = TrainConfigToYaml(config);
  const TrainConfig again = ParseTrainConfig(yaml, "b");
  EXPECT_EQ(TrainConfigToYaml(again), yaml);
  EXPECT_EQ(again.planner, "random");
  EXPECT_EQ(again.ensemble.hidden_sizes, std::vector<int>({8}));
}

TEST(ConfigTest, BadConfigurationsNameTheKeyAndTheValue) {
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planning: {elites: 600}", "c.yaml"); }),
            "config 'c.yaml': planning.elites is 600: expected between 1 and population (500)");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planning: {horizon: 0}", "c.yaml"); }),
            "config 'c.yaml': planning.horizon is 0: expected 1 to 1000 steps");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planner: mppi", "c.yaml"); }),
            "config 'c.yaml': key 'planner' is 'mppi': expected one of rce, cem, random");
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("task: AntGoal1", "c.yaml"); }),
              ::testing::HasSubstr("config 'c.yaml': key 'task': unknown task 'AntGoal1'"));
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("ensemble: {hiden_sizes: [8]}", "c.yaml"); }),
            "config 'c.yaml': unknown key 'ensemble.hiden_sizes': expected one of ensemble_size, "
            "hidden_sizes, predict_delta, learning_rate, batch_size, max_epochs, "
            "validation_fraction, member_subset_fraction, validate_every, patience, init_std, "
            "min_std, precision");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("ensemble: {precision: tf32}", "c.yaml"); }),
            "config 'c.yaml': ensemble.precision is tf32 but device is 'cpu': TF32 is a CUDA "
            "tensor-core format; use fp32 or bf16 on the CPU");
  EXPECT_EQ(
      ErrorMessage([] { ParseTrainConfig("classifier: {safe_selection: oldest}", "c.yaml"); }),
      "config 'c.yaml': classifier.safe_selection is 'oldest': expected 'storage_order' or "
      "'newest'");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("training: {label_every_step: 2}", "c.yaml"); }),
            "config 'c.yaml': key 'training.label_every_step' is '2': expected true or false");
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("colour: blue", "c.yaml"); }),
              ::testing::HasSubstr("unknown key 'colour'"));
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planning: {population: many}", "c.yaml"); }),
            "config 'c.yaml': key 'planning.population' is 'many': expected an integer");
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("variant: standard", "c.yaml"); }),
              ::testing::HasSubstr("training plans on the paper variant"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("planning: [1, 2]", "c.yaml"); }),
              ::testing::HasSubstr("'planning' must be a mapping"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("task: [", "c.yaml"); }),
              ::testing::HasSubstr("config 'c.yaml' is not valid YAML"));
  EXPECT_EQ(ErrorMessage([] { LoadTrainConfig("/nonexistent/x.yaml"); }),
            "config file '/nonexistent/x.yaml' cannot be opened: expected a YAML file");
}

TEST(ConfigTest, OverridesChangeTheirKeysAndAreValidatedAsAFileIs) {
  const TrainConfig base = ParseTrainConfig("planner: cem", "c.yaml");
  const TrainConfig changed =
      ApplyConfigOverrides(base,
                           {"planning.population=300", "classifier.threshold=0.3", "planner=rce",
                            "ensemble.hidden_sizes=[16, 16]"},
                           "--set");
  EXPECT_EQ(changed.planning.cross_entropy.population, 300);
  EXPECT_DOUBLE_EQ(changed.classifier.threshold, 0.3);
  EXPECT_EQ(changed.planner, "rce");
  EXPECT_EQ(changed.ensemble.hidden_sizes, (std::vector<int>{16, 16}));
  // Everything else is the base's.
  EXPECT_EQ(changed.planning.cross_entropy.elites, base.planning.cross_entropy.elites);
  EXPECT_EQ(TrainConfigToYaml(ApplyConfigOverrides(base, {}, "--set")), TrainConfigToYaml(base));

  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"planning.populaton=3"}, "--set"); }),
            "--set 'planning.populaton=3': unknown key 'planning.populaton'");
  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"planning.population"}, "--set"); }),
            "--set 'planning.population': expected section.key=value, e.g. "
            "planning.population=500");
  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"a.b.c=1"}, "--set"); }),
            "--set 'a.b.c=1': expected section.key=value, e.g. planning.population=500");
  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"planning.elites=900"}, "--set"); }),
            "config '--set': planning.elites is 900: expected between 1 and population (500)");
  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"planning.population=x"}, "--set"); }),
            "config '--set': key 'planning.population' is 'x': expected an integer");
}

// Every number a config can give has a bound, checked before the run takes any memory.
TEST(ConfigTest, SizesOutOfTheirBoundsAreNamedBeforeAnythingIsAllocated) {
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planning: {population: 1e12}", "c.yaml"); }),
            "config 'c.yaml': key 'planning.population' is '1e12': expected an integer from "
            "-2147483648 to 2147483647");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("seed: -1", "c.yaml"); }),
            "config 'c.yaml': key 'seed' is '-1': expected an integer from 0 to "
            "18446744073709551615");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planning: {horizon: 1000000000}", "c.yaml"); }),
            "config 'c.yaml': planning.horizon is 1000000000: expected 1 to 1000 steps");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("ensemble: {hidden_sizes: [100000000]}", "c"); }),
            "config 'c': ensemble.hidden_sizes[0] is 100000000: expected a width from 1 to 65536");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planning: {population: 2000000000}", "c"); }),
            "config 'c': planning.population is 2000000000: expected 1 to 1000000");
  EXPECT_EQ(
      ErrorMessage([] { ParseTrainConfig("training: {transition_capacity: 2000000000}", "c"); }),
      "config 'c': training.transition_capacity is 2000000000: expected 2 to 100000000");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("environment: {spawn: floating}", "c"); }),
            "config 'c': environment.spawn: spawn 'floating': expected standing or model-origin");
  EXPECT_EQ(ParseTrainConfig("environment: {spawn: model-origin}", "c").spawn, Spawn::kModelOrigin);
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("variant: foo", "c"); }),
            "config 'c': key 'variant': unknown variant 'foo': expected 'paper' (the paper's "
            "modified tasks), 'standard' (Safety-Gymnasium's stock tasks) or 'paper-lidar' (the "
            "paper's tasks as its model-free baselines observed them)");
  // Each size within its bound, together more than any machine has.
  EXPECT_THAT(ErrorMessage([] {
                ParseTrainConfig(
                    "ensemble: {ensemble_size: 64, hidden_sizes: [65536]}\n"
                    "planning: {population: 1000000, elites: 10, horizon: 1000}",
                    "c");
              }),
              ::testing::AllOf(::testing::HasSubstr("config 'c': the run would need about"),
                               ::testing::HasSubstr("planning (population x members x horizon)"),
                               ::testing::HasSubstr("lower the sizes named")));
}

TEST(ConfigTest, TheMemoryEstimateCountsTheBuffersExactly) {
  const TrainConfig config = ParseTrainConfig(
      "training: {transition_capacity: 1000, safe_capacity: 100, unsafe_capacity: 10}", "c");
  const RunMemory memory = EstimateRunMemory(config, 24, 2);
  EXPECT_DOUBLE_EQ(memory.transitions, 1000.0 * (24 + 24 + 2) * 4);  // state, action, next
  EXPECT_DOUBLE_EQ(memory.labeled_states, 110.0 * 24 * 4);
  EXPECT_GT(memory.ensemble, 4 * 4.0 * (26 * 1024));  // at least the first layer's weights x 4
  EXPECT_GT(memory.planning, 0.0);
  EXPECT_GT(PhysicalMemoryBytes(), 0u);
}

TEST(ConfigTest, EveryPresetInConfigsLoads) {
  int mpc = 0, model_free = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CMBRL_SOURCE_DIR "/configs")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const TrainConfig config = LoadTrainConfig(entry.path().string());
    const std::string name = entry.path().stem().string();
    if (name == "quickstart" || name == "tiny-test") continue;
    // The paper presets: <task>-<method>.yaml with the paper's sizes.
    std::string task = config.task;
    for (char& c : task) c = static_cast<char>(std::tolower(c));
    EXPECT_EQ(name, task + "-" + MethodOf(config));
    if (config.algorithm == "mpc") {
      ++mpc;
      EXPECT_EQ(config.ensemble.hidden_sizes, std::vector<int>({1024, 1024, 1024}));
      EXPECT_EQ(config.ensemble.ensemble_size, config.task.rfind("Car", 0) == 0 ? 5 : 4);
      EXPECT_EQ(config.planning.cross_entropy.population, 500);
    } else {
      ++model_free;
      EXPECT_EQ(config.variant, Variant::kPaperLidar);
      EXPECT_EQ(config.training.total_steps, 10'000'000);
      EXPECT_EQ(config.policy_optimisation.steps_per_epoch, 30000);
      EXPECT_EQ(config.policy_optimisation.policy_hidden, std::vector<int>({256, 256}));
    }
  }
  EXPECT_EQ(mpc, 12);         // 4 tasks x 3 planners
  EXPECT_EQ(model_free, 12);  // 4 tasks x trpo, trpo-lagrangian, cpo
}

// Each preset of a folder of task x planner configs (<task>-<planner>.yaml), as loaded.
void ForEachPreset(const std::string& folder,
                   const std::function<void(const std::string& task, const std::string& planner,
                                            const TrainConfig& config)>& check) {
  int presets = 0;
  for (const std::string task : {"PointGoal1", "PointGoal2", "CarGoal1", "CarGoal2"}) {
    for (const std::string planner : {"rce", "cem", "random"}) {
      std::string stem = task;
      for (char& c : stem) c = static_cast<char>(std::tolower(c));
      const std::string path = folder + "/" + stem + "-" + planner + ".yaml";
      SCOPED_TRACE(path);
      const TrainConfig config = LoadTrainConfig(path);
      EXPECT_EQ(config.task, task);
      EXPECT_EQ(config.planner, planner);
      check(task, planner, config);
      ++presets;
    }
  }
  EXPECT_EQ(presets, 12);
}

TEST(ConfigTest, TheQuickstartGridHasEveryTaskAndPlannerAtQuickstartSize) {
  const TrainConfig quickstart = LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/quickstart.yaml");
  ForEachPreset(CMBRL_SOURCE_DIR "/configs/quickstart",
                [&](const std::string& task, const std::string&, const TrainConfig& config) {
                  EXPECT_EQ(config.ensemble.hidden_sizes, quickstart.ensemble.hidden_sizes);
                  EXPECT_EQ(config.ensemble.ensemble_size, task.rfind("Car", 0) == 0 ? 5 : 4);
                  EXPECT_EQ(config.training.total_steps, quickstart.training.total_steps);
                  EXPECT_EQ(config.planning.cross_entropy.population,
                            quickstart.planning.cross_entropy.population);
                });
}

// The CPU presets: the paper's settings but for the dynamics networks' width, RCE's planner
// (the grid's 200 x 5 with 10 elites: ablation 'population'), the window, for the Car
// networks that predict the change of state (ablation 'delta'), and for the level-2 RCE
// presets' and PointGoal1 CEM's classifier threshold of 0.3 (ablation 'threshold').
TEST(ConfigTest, TheCpuPresetsKeepThePapersSettingsButTheNetworksWidthAndRcesPlanner) {
  const TrainConfig paper = ParseTrainConfig("task: PointGoal1", "paper");
  ForEachPreset(
      CMBRL_SOURCE_DIR "/configs/cpu",
      [&](const std::string& task, const std::string& planner, const TrainConfig& config) {
        EXPECT_EQ(config.variant, Variant::kPaper);
        EXPECT_EQ(config.training.total_steps, 3000);
        EXPECT_EQ(config.ensemble.hidden_sizes, std::vector<int>({256, 256, 256}));
        const bool car = task.rfind("Car", 0) == 0;
        EXPECT_EQ(config.ensemble.ensemble_size, car ? 5 : 4);
        EXPECT_EQ(config.ensemble.predict_delta, car);
        // Everything else as the paper ran it.
        TrainConfig expected = paper;
        expected.task = config.task;
        expected.planner = config.planner;
        expected.training.total_steps = config.training.total_steps;
        expected.ensemble.hidden_sizes = config.ensemble.hidden_sizes;
        expected.ensemble.ensemble_size = config.ensemble.ensemble_size;
        expected.ensemble.predict_delta = config.ensemble.predict_delta;
        expected.objective.goal_index = config.objective.goal_index;
        // Named departures of two presets (their configs say why).
        if ((task == "CarGoal2" && planner == "rce") ||
            (task == "PointGoal2" && planner == "rce") ||
            (task == "PointGoal1" && planner == "cem")) {
          expected.classifier.threshold = 0.3;
        }
        if (planner == "rce") {
          expected.planning.cross_entropy.population = 200;
          expected.planning.cross_entropy.elites = 10;
          expected.planning.cross_entropy.max_iterations = 5;
        }
        EXPECT_EQ(TrainConfigToYaml(config), TrainConfigToYaml(expected));
      });
}

// The level-2 ablation 'combined' is the CPU preset at the 2000-step screening window, so that
// its runs continued to the CPU grid's 3000 steps (cmbrl train --resume --steps). Its Car configs
// record runs made before the Car presets predicted the change of state, and CarGoal2's before
// its preset's classifier threshold of 0.3; they differ in that.
TEST(ConfigTest, TheCombinedAblationIsTheCpuPresetAtTwoThousandSteps) {
  int checked = 0;
  for (const std::string name : {"pointgoal2-rce", "cargoal2-rce", "cargoal1-cem"}) {
    SCOPED_TRACE(name);
    TrainConfig combined =
        LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/ablation-level2/combined/" + name + ".yaml");
    const TrainConfig preset = LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/cpu/" + name + ".yaml");
    EXPECT_EQ(combined.training.total_steps, 2000);
    combined.training.total_steps = preset.training.total_steps;
    EXPECT_EQ(combined.ensemble.predict_delta, false);
    combined.ensemble.predict_delta = preset.ensemble.predict_delta;
    EXPECT_DOUBLE_EQ(combined.classifier.threshold, 0.5);
    combined.classifier.threshold = preset.classifier.threshold;
    EXPECT_EQ(TrainConfigToYaml(combined), TrainConfigToYaml(preset));
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

// The ablation 'delta' became the Car presets: each of its configs is the Car preset at the
// 2000-step screening window, so its runs continue into the CPU grid's cells (CarGoal2 RCE's
// until its preset took the classifier threshold of 0.3).
TEST(ConfigTest, TheDeltaAblationIsTheCarPresetAtTwoThousandSteps) {
  int checked = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(CMBRL_SOURCE_DIR "/configs/ablation-level2/delta")) {
    const std::string name = entry.path().stem().string();
    SCOPED_TRACE(name);
    TrainConfig delta = LoadTrainConfig(entry.path().string());
    const TrainConfig preset = LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/cpu/" + name + ".yaml");
    EXPECT_TRUE(delta.ensemble.predict_delta);
    EXPECT_EQ(delta.training.total_steps, 2000);
    delta.training.total_steps = preset.training.total_steps;
    EXPECT_DOUBLE_EQ(delta.classifier.threshold, 0.5);
    delta.classifier.threshold = preset.classifier.threshold;
    EXPECT_EQ(TrainConfigToYaml(delta), TrainConfigToYaml(preset));
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST(ConfigTest, ThePointGoal1DeltaAblationIsThePresetPredictingTheChange) {
  TrainConfig delta =
      LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/ablation-pointgoal1/delta/pointgoal1-cem.yaml");
  const TrainConfig preset = LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/cpu/pointgoal1-cem.yaml");
  EXPECT_TRUE(delta.ensemble.predict_delta);
  EXPECT_FALSE(preset.ensemble.predict_delta);
  delta.ensemble.predict_delta = false;
  // Made before the preset took the classifier threshold of 0.3.
  EXPECT_DOUBLE_EQ(delta.classifier.threshold, 0.5);
  delta.classifier.threshold = preset.classifier.threshold;
  EXPECT_EQ(TrainConfigToYaml(delta), TrainConfigToYaml(preset));
}

// The ablation 'threshold' became the PointGoal1 CEM preset: the same 3000 steps, so its runs are
// the CPU grid's cell.
TEST(ConfigTest, ThePointGoal1ThresholdAblationIsThePreset) {
  const TrainConfig ablation = LoadTrainConfig(
      CMBRL_SOURCE_DIR "/configs/ablation-pointgoal1/threshold/pointgoal1-cem.yaml");
  const TrainConfig preset = LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/cpu/pointgoal1-cem.yaml");
  EXPECT_DOUBLE_EQ(preset.classifier.threshold, 0.3);
  EXPECT_EQ(TrainConfigToYaml(ablation), TrainConfigToYaml(preset));
}

// The ablation 'threshold' became the level-2 RCE presets: the preset at 2000 steps, so its
// runs (continued to, or run for, 3000 steps with --steps) are the CPU grid's cells.
TEST(ConfigTest, TheLevel2ThresholdAblationIsThePresetAtTwoThousandSteps) {
  for (const std::string name : {"cargoal2-rce", "pointgoal2-rce"}) {
    SCOPED_TRACE(name);
    TrainConfig ablation =
        LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/ablation-level2/threshold/" + name + ".yaml");
    const TrainConfig preset = LoadTrainConfig(CMBRL_SOURCE_DIR "/configs/cpu/" + name + ".yaml");
    EXPECT_EQ(ablation.training.total_steps, 2000);
    EXPECT_DOUBLE_EQ(ablation.classifier.threshold, 0.3);
    EXPECT_DOUBLE_EQ(preset.classifier.threshold, 0.3);
    ablation.training.total_steps = preset.training.total_steps;
    EXPECT_EQ(TrainConfigToYaml(ablation), TrainConfigToYaml(preset));
  }
}

TEST(ConfigTest, ObservationSizesMatchTheEnvironments) {
  for (const std::string& task : EnvNames()) {
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      EXPECT_EQ(ObservationSize(GoalTaskSpecByName(task, variant)),
                MakeEnv(task, variant)->observation_spec().size())
          << task << " " << VariantName(variant);
    }
  }
}

}  // namespace
}  // namespace cmbrl

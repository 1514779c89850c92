#include "cmbrl/config/config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <sys/stat.h>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <yaml-cpp/yaml.h>

#include "cmbrl/core/memory.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/env/tasks/task_spec.h"
#include "cmbrl/planning/reward_term.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

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

// Absurd finite values of the keys the last probe found training on (or failing at run time
// without a name) are refused under their key.
TEST(ConfigTest, AbsurdFiniteValuesAreRefusedByTheirKey) {
  const std::vector<std::string> keys = {
      "ensemble: {min_std: 1e300}",          "ensemble: {init_std: 1e300}",
      "ensemble: {learning_rate: 1e300}",    "planning: {epsilon: 1e300}",
      "planning: {penalty: 1e300}",          "planning: {initial_variance: 1e300}",
      "objective: {near_goal_radius: 1e300}", "objective: {at_goal_bonus: 1e300}",
      "classifier: {learning_rate: 1e300}",  "training: {pretrain_episodes: 0}",
      "classifier: {min_child_weight: 1e300}", "classifier: {l2_regularization: 1e300}",
      "planning: {action_high: 1e300}",
      "{algorithm: trpo, variant: paper-lidar, policy_optimisation: {damping: 1e300}}",
      "{algorithm: trpo, variant: paper-lidar, policy_optimisation: {target_kl: 1e300}}",
      "{algorithm: trpo, variant: paper-lidar, policy_optimisation: {value_learning_rate: 1e300}}"};
  for (const std::string& yaml : keys) {
    SCOPED_TRACE(yaml);
    const std::string message = ErrorMessage([&] { ParseTrainConfig(yaml, "c.yaml"); });
    const std::string key = yaml.substr(yaml.rfind('{') + 1, yaml.find(':', yaml.rfind('{')) -
                                                                  yaml.rfind('{') - 1);
    EXPECT_THAT(message, ::testing::HasSubstr(key)) << message;
    EXPECT_THAT(message, ::testing::HasSubstr("expected")) << message;
  }
}

// The navigation suite's other families exist in the stock variant only, which is then their
// default; each plans with its own lidar form, which a paper variant's observation lacks.
TEST(ConfigTest, TheOtherFamiliesAreStockTasksWithLidarRewards) {
  const TrainConfig button = ParseTrainConfig("task: PointButton1", "c.yaml");
  EXPECT_EQ(button.variant, Variant::kStandard);
  EXPECT_EQ(AnalyticRewardForm(button), "goal-lidar-distance");
  EXPECT_EQ(AnalyticRewardForm(ParseTrainConfig("task: CarPush2", "c.yaml")),
            "push-lidar-distances");
  EXPECT_EQ(AnalyticRewardForm(ParseTrainConfig("task: PointCircle0", "c.yaml")),
            "circle-lidar-speed");
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("{task: PointButton1, variant: paper}", "c.yaml"); }),
              ::testing::HasSubstr("task 'PointButton1' has no variant 'paper'"));
  EXPECT_THAT(ErrorMessage([] {
                ParseTrainConfig("objective: {analytic_form: circle-lidar-speed}", "c.yaml");
              }),
              ::testing::HasSubstr("the analytic reward 'circle-lidar-speed' reads a lidar "
                                   "observation: key 'variant' is 'paper'"));
  // The stock Goal tasks plan with the goal's lidar when asked to.
  const TrainConfig goal = ParseTrainConfig(
      "{variant: standard, objective: {analytic_form: goal-lidar-distance}}", "c.yaml");
  EXPECT_EQ(AnalyticRewardForm(goal), "goal-lidar-distance");
  // Every preset of the new tasks reads.
  for (const TaskEntry& task : Tasks()) {
    if (HasPaperVariant(task)) continue;
    for (const std::string method : {"rce", "cem", "random"}) {
      std::string lower = task.name;
      std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
      const TrainConfig preset = LoadTrainConfig(std::string(CMBRL_SOURCE_DIR) + "/configs/" +
                                                 lower + "-" + method + ".yaml");
      EXPECT_EQ(preset.task, task.name);
      EXPECT_EQ(preset.planner, method);
    }
  }
}

// objective.reward: the Goal tasks plan with their own analytic form; every task names a form
// that planning knows, and a source that is not offered is named by its key.
TEST(ConfigTest, TheRewardTermIsTheTasksAnalyticForm) {
  EXPECT_EQ(ParseTrainConfig("{}", "empty").objective.reward, "analytic");
  const std::vector<std::string> forms = AnalyticRewardNames();
  for (const TaskEntry& task : Tasks()) {
    EXPECT_NE(std::find(forms.begin(), forms.end(), task.analytic_reward), forms.end())
        << task.name;
  }
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("objective: {reward: guessed}", "c"); }),
              ::testing::HasSubstr("config 'c': objective.reward is 'guessed': expected one of "
                                   "analytic, learned, python"));
  EXPECT_EQ(ParseTrainConfig("objective: {reward: learned}", "c").objective.reward, "learned");
  // A misspelt source or form is answered with the one it most likely meant.
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("objective: {reward: lerned}", "c"); }),
              ::testing::HasSubstr("objective.reward is 'lerned' (did you mean 'learned'?): "
                                   "expected one of"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("objective: {termination: nnoe}", "c"); }),
              ::testing::HasSubstr("objective.termination is 'nnoe' (did you mean 'none'?)"));
  EXPECT_THAT(
      ErrorMessage([] {
        ParseTrainConfig("{variant: standard, objective: {analytic_form: goal-distanse}}", "c");
      }),
      ::testing::HasSubstr("is 'goal-distanse' (did you mean 'goal-distance'?)"));
  EXPECT_THAT(ErrorMessage([] {
                MakeAnalyticReward("goal-lidar-distanse", {}, {}, LidarGeometry{3.0, 1.0});
              }),
              ::testing::HasSubstr("unknown analytic reward 'goal-lidar-distanse' (did you mean "
                                   "'goal-lidar-distance'?)"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("reward_model: {hidden_sizes: []}", "c"); }),
              ::testing::HasSubstr("reward_model.hidden_sizes has 0 layers: expected 1 to 16"));
}

// A task given from Python ("python:..."): its sizes are recorded (environment.observation_size
// and action_size, which a built-in task must leave at 0), and it plans with a Python or learned
// reward, or an analytic form that the config names.
TEST(ConfigTest, ATaskGivenFromPythonRecordsItsSizesAndNamesItsReward) {
  const std::string task = "{task: 'python:m.make()', environment: {observation_size: 4, "
                           "action_size: 2}, ";
  const TrainConfig config = ParseTrainConfig(task + "objective: {reward: python}}", "c");
  EXPECT_EQ(config.task, "python:m.make()");
  EXPECT_EQ(config.observation_size, 4);
  EXPECT_EQ(config.action_size, 2);
  EXPECT_EQ(ParseTrainConfig(TrainConfigToYaml(config), "again").task, config.task);
  // The goal-distance form reads the goal at goal_index: a 4-value state has none at 6.
  EXPECT_THAT(ErrorMessage([&] {
                ParseTrainConfig(task + "objective: {analytic_form: goal-distance}}", "c");
              }),
              ::testing::HasSubstr("goal_index is 6: expected 0 to 2"));
  EXPECT_THAT(ErrorMessage([&] { ParseTrainConfig(task + "}", "c"); }),
              ::testing::HasSubstr("which has no analytic reward of its own: give a reward "
                                   "function"));
  EXPECT_THAT(ErrorMessage([&] {
                ParseTrainConfig(task + "objective: {analytic_form: sideways}}", "c");
              }),
              ::testing::HasSubstr("is 'sideways' (objective.analytic_form, or the task's own): "
                                   "expected one of goal-distance"));
  EXPECT_THAT(ErrorMessage([] {
                ParseTrainConfig("{task: 'python:m.make()', objective: {reward: python}}", "c");
              }),
              ::testing::HasSubstr("'environment.observation_size' and 'environment.action_size' "
                                   "are 0 and 0: a Python environment's run records its sizes"));
  EXPECT_THAT(ErrorMessage([] {
                ParseTrainConfig("{environment: {observation_size: 4, action_size: 2}}", "c");
              }),
              ::testing::HasSubstr("they are a Python environment's, and task 'PointGoal1' is "
                                   "built in (expected 0)"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("{task: 'python:'}", "c"); }),
              ::testing::HasSubstr("expected what made the environment after 'python:'"));
}

// A Python environment and functions declared by name (section python): the task is what makes
// the env unless the file names one of its own; a declared function plans with it; each bad
// name or combination is refused by its key; relative folders are the config file's.
TEST(ConfigTest, PythonPartsDeclaredByNameNameTheTaskAndTheObjective) {
  const std::string env = "python: {env: 'my_envs.walls:make', reward: 'my_envs.walls:reward'";
  const TrainConfig made = ParseTrainConfig(env + "}", "c");
  EXPECT_EQ(made.task, "python:my_envs.walls.make()");
  EXPECT_EQ(made.objective.reward, "python");
  EXPECT_EQ(made.observation_size, 0);  // recorded once the env is made
  EXPECT_EQ(ParseTrainConfig(TrainConfigToYaml(made), "again").task, made.task);
  EXPECT_EQ(ParseTrainConfig("task: Walls\n" + env + "}", "c").task, "Walls");
  EXPECT_EQ(ParseTrainConfig(env + ", termination: 'm:ends'}", "c").objective.termination,
            "python");
  EXPECT_THAT(ErrorMessage([&] { ParseTrainConfig("task: PointGoal1\n" + env + "}", "c"); }),
              ::testing::HasSubstr("key 'task' is 'PointGoal1' with python.env 'my_envs.walls:make' "
                                   "declared: expected a name of its own"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("python: {env: 'my_envs.make'}", "c"); }),
              ::testing::HasSubstr("python.env is 'my_envs.make': expected 'module:attribute'"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("python: {reward: 'm:1f'}", "c"); }),
              ::testing::HasSubstr("python.reward is 'm:1f': expected 'module:attribute'"));
  EXPECT_THAT(ErrorMessage([&] {
                ParseTrainConfig(env + "}\nobjective: {reward: learned}", "c");
              }),
              ::testing::HasSubstr("key 'objective.reward' is 'learned' with python.reward "
                                   "'my_envs.walls:reward' declared: leave one out"));
  EXPECT_THAT(ErrorMessage([&] {
                ParseTrainConfig(env + ", termination: 'm:t'}\nobjective: {termination: learned}",
                                 "c");
              }),
              ::testing::HasSubstr("key 'objective.termination' is 'learned' with "
                                   "python.termination 'm:t' declared"));
  const std::filesystem::path folder = testing::TestTempDir() / "declared";
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "task.yaml") << env << ", path: [envs, ., /abs]}\n";
  const TrainConfig read = LoadTrainConfig((folder / "task.yaml").string());
  EXPECT_EQ(read.python.path, (std::vector<std::string>{(folder / "envs").string(),
                                                         folder.string(), "/abs"}));
}

// A config is bounded before it is read: a regular file of at most 1 MiB, no anchors or aliases
// (an alias bomb would expand exponentially), no type tags, a bounded depth; a key without a
// value (a bare section) and a quoted number are refused by name, from a file, a dict's text or
// an override alike. Each refusal is quick.
TEST(ConfigTest, InputsAreBoundedBeforeTheyAreRead) {
  const auto refused = [](const std::string& text) {
    return ErrorMessage([&] { ParseTrainConfig("task: PointGoal1\n" + text, "c"); });
  };
  std::string bomb = "a: &a [1, 1]\n";
  for (char c = 'b'; c <= 'z'; ++c) {
    bomb += fmt::format("{0}: &{0} [*{1}, *{1}, *{1}, *{1}]\n", c, static_cast<char>(c - 1));
  }
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THAT(refused(bomb), ::testing::HasSubstr("line 2: YAML anchors (&name) are not accepted"));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_THAT(refused("planning: {population: !!str 24}"),
              ::testing::HasSubstr("the YAML tag 'tag:yaml.org,2002:str' is not accepted"));
  EXPECT_THAT(refused("planning:\n"),
              ::testing::HasSubstr("key 'planning' has no value: give it one"));
  EXPECT_THAT(refused("planning: {population: '24'}"),
              ::testing::HasSubstr("key 'planning.population' is '24', a string: expected an "
                                   "integer (write it without quotes)"));
  EXPECT_THAT(refused("ensemble: {hidden_sizes: ['64']}"),
              ::testing::HasSubstr("key 'ensemble.hidden_sizes' is '[64]', a string"));
  EXPECT_EQ(ParseTrainConfig("task: PointGoal1\ndevice: 'cpu'", "c").device, "cpu");  // a string
  std::string deep = "x: ";
  for (int i = 0; i < 40; ++i) deep += "[";
  EXPECT_THAT(refused(deep), ::testing::HasSubstr("nested more than 16 levels deep"));
  EXPECT_THAT(refused("x: " + std::string(2 << 20, 'a')),
              ::testing::HasSubstr("bytes: a config is at most 1048576 bytes (1 MiB)"));
  EXPECT_THAT(ErrorMessage([] {
                ApplyConfigOverrides(ParseTrainConfig("task: PointGoal1", "c"),
                                     {"planning.population='24'"}, "--set");
              }),
              ::testing::HasSubstr("a string: expected an integer"));
  EXPECT_THAT(ErrorMessage([] {
                ApplyConfigOverrides(ParseTrainConfig("task: PointGoal1", "c"),
                                     {"planning.population=~"}, "--set");
              }),
              ::testing::HasSubstr("the value is null"));
  // Only a regular file is read.
  EXPECT_THAT(ErrorMessage([] { LoadTrainConfig("/dev/zero"); }),
              ::testing::HasSubstr("is not a regular file (a folder, a FIFO or a device)"));
  const std::filesystem::path folder = testing::TestTempDir() / "bounded";
  std::filesystem::create_directories(folder);
  EXPECT_THAT(ErrorMessage([&] { LoadTrainConfig(folder.string()); }),
              ::testing::HasSubstr("is not a regular file"));
  const std::filesystem::path fifo = folder / "fifo.yaml";
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THAT(ErrorMessage([&] { LoadTrainConfig(fifo.string()); }),
              ::testing::HasSubstr("is not a regular file"));
  const std::filesystem::path big = folder / "big.yaml";
  std::ofstream(big) << "task: PointGoal1\n# " << std::string(2 << 20, 'x') << "\n";
  EXPECT_THAT(ErrorMessage([&] { LoadTrainConfig(big.string()); }),
              ::testing::HasSubstr("bytes: a config is at most 1048576 bytes (1 MiB)"));
  const std::filesystem::path loop = folder / "loop.yaml";
  std::filesystem::remove(loop);
  std::filesystem::create_symlink(loop, loop);
  EXPECT_THAT(ErrorMessage([&] { LoadTrainConfig(loop.string()); }),
              ::testing::HasSubstr("cannot be read: Too many levels of symbolic links"));
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
            "config 'c.yaml': key 'planner' is 'mppi': expected one of rce, cem, random, rce-icem");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("planner: rce-icme", "c.yaml"); }),
            "config 'c.yaml': key 'planner' is 'rce-icme' (did you mean 'rce-icem'?): expected one "
            "of rce, cem, random, rce-icem");
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("task: CarGaol2", "c.yaml"); }),
              ::testing::HasSubstr("unknown task 'CarGaol2' (did you mean 'CarGoal2'?)"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("algorithm: trpo-lagrangain", "c.yaml"); }),
              ::testing::HasSubstr("'trpo-lagrangain' (did you mean 'trpo-lagrangian'?)"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("task: AntGoal1", "c.yaml"); }),
              ::testing::HasSubstr("config 'c.yaml': key 'task': unknown task 'AntGoal1'"));
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("ensemble: {hiden_sizes: [8]}", "c.yaml"); }),
            "config 'c.yaml': unknown key 'ensemble.hiden_sizes' (did you mean "
            "'ensemble.hidden_sizes'?): expected one of ensemble_size, "
            "hidden_sizes, predict_delta, learning_rate, batch_size, max_epochs, "
            "validation_fraction, member_subset_fraction, validate_every, patience, init_std, "
            "min_std, precision, backend");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("ensemble: {precision: tf32}", "c.yaml"); }),
            "config 'c.yaml': ensemble.precision is tf32 but device is 'cpu': TF32 is a CUDA "
            "tensor-core format; use fp32 or bf16 on the CPU");
  EXPECT_EQ(ErrorMessage([] { ParseTrainConfig("ensemble: {backend: mkl}", "c.yaml"); }),
            "config 'c.yaml': ensemble.backend is 'mkl': expected auto, libtorch or onednn");
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
              ::testing::HasSubstr("the goal-distance reward plans on the paper variant's "
                                   "ego-state vector (the standard variant observes lidar: plan "
                                   "with objective.analytic_form: goal-lidar-distance)"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("planning: [1, 2]", "c.yaml"); }),
              ::testing::HasSubstr("'planning' must be a mapping"));
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("task: [", "c.yaml"); }),
              ::testing::HasSubstr("config 'c.yaml' is not valid YAML"));
  EXPECT_EQ(ErrorMessage([] { LoadTrainConfig("/nonexistent/x.yaml"); }),
            "config file '/nonexistent/x.yaml' does not exist: expected a YAML file");
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
            "--set 'planning.populaton=3': unknown key 'planning.populaton' (did you mean "
            "'planning.population'?)");
  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"planing.population=3"}, "--set"); }),
            "--set 'planing.population=3': unknown key 'planing.population' (did you mean "
            "'planning.population'?)");
  EXPECT_EQ(ErrorMessage([&] { ApplyConfigOverrides(base, {"colour=blue"}, "--set"); }),
            "--set 'colour=blue': unknown key 'colour'");
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
  EXPECT_TRUE(ParseTrainConfig("environment: {previous_action: true}", "c").previous_action);
  EXPECT_FALSE(ParseTrainConfig("task: CarGoal2", "c").previous_action);
  EXPECT_THAT(ErrorMessage([] { ParseTrainConfig("environment: {previous_action: 2}", "c"); }),
              ::testing::HasSubstr("environment.previous_action"));
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

// A model-free run is bounded too: its networks and its epoch's batch.
TEST(ConfigTest, AModelFreeRunTooLargeForTheMachineIsRefusedByItsKeys) {
  const std::string base = "task: PointGoal1\nvariant: paper-lidar\nalgorithm: trpo\n";
  EXPECT_THAT(ErrorMessage([&] {
                ParseTrainConfig(base + "policy_optimisation: {policy_hidden: [65536, 65536]}",
                                 "c");
              }),
              ::testing::AllOf(::testing::HasSubstr("config 'c': the run would need about"),
                               ::testing::HasSubstr("policy_optimisation.policy_hidden"),
                               ::testing::HasSubstr("lower the sizes named")));
  EXPECT_THAT(ErrorMessage([&] {
                ParseTrainConfig(base + "policy_optimisation: {steps_per_epoch: 100000000, "
                                        "value_hidden: [4096, 4096]}",
                                 "c");
              }),
              ::testing::HasSubstr("policy_optimisation.steps_per_epoch"));
  const TrainConfig small = ParseTrainConfig(
      base + "policy_optimisation: {steps_per_epoch: 1000, envs: 1, policy_hidden: [10], "
             "value_hidden: [10]}",
      "c");
  const RunMemory memory = EstimateRunMemory(small, 60, 2);
  const double policy = (61.0 * 10 + 11 * 2 + 2), value = 61.0 * 10 + 11;
  EXPECT_DOUBLE_EQ(memory.policy_networks, (8 * policy + 8 * value) * 4);
  EXPECT_DOUBLE_EQ(memory.epoch_batch, 1000.0 * (60 + 2 + 8) * 4 + 3 * 1000.0 * 30 * 4);
  EXPECT_EQ(memory.transitions + memory.ensemble + memory.planning, 0.0);
}

TEST(ConfigTest, EveryPresetInConfigsLoads) {
  int mpc = 0, model_free = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CMBRL_SOURCE_DIR "/configs")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const TrainConfig config = LoadTrainConfig(entry.path().string());
    const std::string name = entry.path().stem().string();
    // The preset families, composed over these.
    if (name == "quickstart" || name == "cpu") continue;
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
  EXPECT_EQ(mpc, 12 + 54);     // 4 Goal tasks x 3 planners; 18 stock tasks x 3 planners
  EXPECT_EQ(model_free, 12);  // 4 tasks x trpo, trpo-lagrangian, cpo
}

// The paper's preset of every task and MPC method with a family composed over it (LoadTrainConfig
// of two files), as `cmbrl train --config PRESET FAMILY` and the experiments resolve it.
void ForEachFamilyPreset(const std::string& family,
                         const std::function<void(const std::string& task,
                                                  const std::string& planner,
                                                  const TrainConfig& paper,
                                                  const TrainConfig& config)>& check) {
  int presets = 0;
  for (const std::string task : {"PointGoal1", "PointGoal2", "CarGoal1", "CarGoal2"}) {
    for (const std::string planner : {"rce", "cem", "random"}) {
      std::string stem = task;
      for (char& c : stem) c = static_cast<char>(std::tolower(c));
      const std::string path = CMBRL_SOURCE_DIR "/configs/" + stem + "-" + planner + ".yaml";
      SCOPED_TRACE(path + " + " + family);
      const TrainConfig paper = LoadTrainConfig(path);
      const TrainConfig config = LoadTrainConfig(std::vector<std::string>{path, family});
      EXPECT_EQ(config.task, task);
      EXPECT_EQ(config.planner, planner);
      check(task, planner, paper, config);
      ++presets;
    }
  }
  EXPECT_EQ(presets, 12);
}

// The CPU family changes the same keys of every task and method, and only those: the window,
// the networks' width, the population (RCE and CEM alike) and random shooting's samples by the
// same factor (experiments/cpu-grid/README.md says why).
TEST(ConfigTest, TheCpuFamilyChangesTheSameKeysOfEveryPreset) {
  ForEachFamilyPreset(
      CMBRL_SOURCE_DIR "/configs/cpu.yaml",
      [](const std::string&, const std::string&, const TrainConfig& paper,
         const TrainConfig& config) {
        EXPECT_EQ(config.training.total_steps, 3000);
        EXPECT_EQ(config.ensemble.hidden_sizes, std::vector<int>({256, 256, 256}));
        EXPECT_EQ(config.planning.cross_entropy.population, 100);
        // Random shooting scores as many sequences as the CE iterations (paper: 5000 for 500).
        EXPECT_EQ(config.planning.random.samples * paper.planning.cross_entropy.population,
                  paper.planning.random.samples * config.planning.cross_entropy.population);
        TrainConfig expected = paper;
        expected.training.total_steps = config.training.total_steps;
        expected.ensemble.hidden_sizes = config.ensemble.hidden_sizes;
        expected.planning.cross_entropy.population = config.planning.cross_entropy.population;
        expected.planning.random.samples = config.planning.random.samples;
        EXPECT_EQ(TrainConfigToYaml(config), TrainConfigToYaml(expected));
      });
}

TEST(ConfigTest, TheQuickstartFamilyIsSmallerThanThePaperForEveryPreset) {
  ForEachFamilyPreset(
      CMBRL_SOURCE_DIR "/configs/quickstart.yaml",
      [](const std::string& task, const std::string&, const TrainConfig& paper,
         const TrainConfig& config) {
        EXPECT_EQ(config.ensemble.hidden_sizes, std::vector<int>({200, 200}));
        EXPECT_EQ(config.ensemble.ensemble_size, task.rfind("Car", 0) == 0 ? 5 : 4);
        EXPECT_EQ(config.training.total_steps, 3000);
        EXPECT_LT(config.planning.cross_entropy.population,
                  paper.planning.cross_entropy.population);
      });
}

// Composing files merges their mappings key by key: a later file names only what it changes.
TEST(ConfigTest, LaterFilesChangeOnlyTheKeysTheyName) {
  const std::filesystem::path dir =
      std::filesystem::path(testing::TestTempPath("compose"));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "base.yaml") << "task: CarGoal2\nplanner: cem\nplanning: {population: 300, "
                                      "elites: 20}\nensemble: {ensemble_size: 5}\n";
  std::ofstream(dir / "over.yaml") << "planning: {population: 100}\n";
  const TrainConfig config = LoadTrainConfig(
      std::vector<std::string>{(dir / "base.yaml").string(), (dir / "over.yaml").string()});
  EXPECT_EQ(config.task, "CarGoal2");
  EXPECT_EQ(config.planning.cross_entropy.population, 100);
  EXPECT_EQ(config.planning.cross_entropy.elites, 20);  // kept from the base
  EXPECT_EQ(config.ensemble.ensemble_size, 5);
  std::ofstream(dir / "bad.yaml") << "planning: {popsize: 100}\n";
  EXPECT_THAT(ErrorMessage([&] {
                LoadTrainConfig(std::vector<std::string>{(dir / "base.yaml").string(),
                                                         (dir / "bad.yaml").string()});
              }),
              ::testing::HasSubstr("unknown key 'planning.popsize'"));
  std::ofstream(dir / "list.yaml") << "- 1\n- 2\n";
  EXPECT_THAT(ErrorMessage([&] {
                LoadTrainConfig(std::vector<std::string>{(dir / "list.yaml").string()});
              }),
              ::testing::HasSubstr("line 1: the document is not a mapping"));
}

// What YAML accepts but a config cannot mean is refused, naming the file and the line.
TEST(ConfigTest, OddDocumentsAreRefusedWithTheirLine) {
  const auto error = [](const std::string& yaml) {
    return ErrorMessage([&] { ParseTrainConfig(yaml, "odd.yaml"); });
  };
  EXPECT_THAT(error(""), ::testing::HasSubstr("config 'odd.yaml' is empty"));
  EXPECT_THAT(error("# only a comment\n"), ::testing::HasSubstr("is empty"));
  EXPECT_THAT(error("task: PointGoal1\n---\ntask: CarGoal1\n"),
              ::testing::HasSubstr("holds 2 YAML documents"));
  EXPECT_THAT(error("task: PointGoal1\ntask: CarGoal1\n"),
              ::testing::HasSubstr("line 2: key 'task' is given twice"));
  EXPECT_THAT(error("task: PointGoal1\nplanning:\n  population: 3\n  elites: 2\n"
                    "  population: 30\n"),
              ::testing::HasSubstr("line 5: key 'population' is given twice"));
  EXPECT_THAT(error("- task\n"), ::testing::HasSubstr("line 1: the document is not a mapping"));
  EXPECT_THAT(error("ensemble: {hidden_sizes: []}\n"),
              ::testing::HasSubstr("hidden_sizes has 0 layers: expected 1 to 16"));
  EXPECT_THAT(error("variant: paper-lidar\nalgorithm: cpo\n"
                    "policy_optimisation: {policy_hidden: []}\n"),
              ::testing::HasSubstr("policy_hidden: 0 hidden layers given"));
  EXPECT_NO_THROW(ParseTrainConfig("{}", "empty mapping"));  // the paper's settings, asked for
}

// `--set section={key: value}` merges into the section: the section's other keys stay.
TEST(ConfigTest, AnOverrideWithAMappingMergesIntoItsSection) {
  const TrainConfig base = ParseTrainConfig("task: PointGoal1\nplanning: {elites: 20}", "base");
  const TrainConfig changed =
      ApplyConfigOverrides(base, {"planning={population: 30}"}, "--set");
  EXPECT_EQ(changed.planning.cross_entropy.population, 30);
  EXPECT_EQ(changed.planning.cross_entropy.elites, 20);
}

// No two files under configs/ differ in a single key other than the task or the method: a
// preset that restates another with one key changed belongs in an experiment as an override.
// The family files (no task of their own) are compared as composed over each paper preset.
TEST(ConfigTest, NoTwoPresetsDifferInOneKeyOtherThanTaskOrMethod) {
  std::vector<std::pair<std::string, YAML::Node>> presets;
  const auto add = [&](const std::string& name, const TrainConfig& config) {
    presets.emplace_back(name, YAML::Load(TrainConfigToYaml(config)));
  };
  std::vector<std::string> families, paper;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(CMBRL_SOURCE_DIR "/configs")) {
    if (entry.path().extension() != ".yaml") continue;
    const YAML::Node file = YAML::LoadFile(entry.path().string());
    if (!file["task"]) {
      families.push_back(entry.path().string());
    } else {
      paper.push_back(entry.path().string());
      add(entry.path().string(), LoadTrainConfig(entry.path().string()));
    }
  }
  ASSERT_GE(paper.size(), 24u);
  ASSERT_EQ(families.size(), 2u);  // cpu, quickstart
  for (const std::string& family : families) {
    for (const std::string& preset : paper) {
      const TrainConfig config = LoadTrainConfig(preset);
      if (config.algorithm != "mpc") continue;  // the families size MPC runs
      add(preset + " + " + family, LoadTrainConfig(std::vector<std::string>{preset, family}));
    }
  }
  int compared = 0;
  for (size_t a = 0; a < presets.size(); ++a) {
    for (size_t b = a + 1; b < presets.size(); ++b) {
      std::vector<std::string> differing;
      for (const auto& section : presets[a].second) {
        const std::string name = section.first.as<std::string>();
        if (name == "task" || name == "planner" || name == "algorithm") continue;
        if (section.second.IsMap()) {
          for (const auto& key : section.second) {
            const std::string k = key.first.as<std::string>();
            if (YAML::Dump(key.second) != YAML::Dump(presets[b].second[name][k])) {
              differing.push_back(name + "." + k);
            }
          }
        } else if (YAML::Dump(section.second) != YAML::Dump(presets[b].second[name])) {
          differing.push_back(name);
        }
      }
      // The method's own keys (the model-free penalty) come with the method.
      const bool same_task_and_method =
          YAML::Dump(presets[a].second["task"]) == YAML::Dump(presets[b].second["task"]) &&
          YAML::Dump(presets[a].second["planner"]) == YAML::Dump(presets[b].second["planner"]) &&
          YAML::Dump(presets[a].second["algorithm"]) ==
              YAML::Dump(presets[b].second["algorithm"]);
      EXPECT_FALSE(same_task_and_method && differing.size() == 1)
          << presets[a].first << " and " << presets[b].first << " differ only in "
          << differing.front();
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

TEST(ConfigTest, ObservationSizesMatchTheEnvironments) {
  for (const TaskEntry& entry : Tasks()) {
    const std::string& task = entry.name;
    for (const Variant variant : {Variant::kPaper, Variant::kStandard}) {
      if (IsPaperWorld(variant) && !HasPaperVariant(entry)) continue;
      EXPECT_EQ(ObservationSize(NavigationTaskSpecByName(task, variant)),
                MakeEnv(task, variant)->observation_spec().size())
          << task << " " << VariantName(variant);
    }
  }
}

// ConfigDifferences visits every key of the config: one changed key, one difference.
TEST(ConfigTest, ConfigDifferencesNamesEachChangedKey) {
  TrainConfig a, b;
  EXPECT_TRUE(ConfigDifferences(a, b).empty());
  b.classifier.safe_selection = "newest";
  b.seed = 7;  // names the run, not its method
  b.objective.beta = 0.5;
  const std::vector<ConfigDifference> differences = ConfigDifferences(a, b);
  ASSERT_EQ(differences.size(), 2u);
  EXPECT_EQ(differences[0].key, "classifier.safe_selection");
  EXPECT_EQ(differences[1].key, "objective.beta");
  EXPECT_EQ(differences[1].ours, "0.4");
  EXPECT_EQ(differences[1].theirs, "0.5");
}

}  // namespace
}  // namespace cmbrl

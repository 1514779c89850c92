// Every numeric key of the config, walked: each given 0, -1, NaN, infinity, 1e300 and a value of
// the wrong type is refused when the config is read, naming the key, or the run trains with it.
// The keys come from the config's own writer (every key it knows, with its default), so a key
// added later is walked without a change here.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/train/trainer.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {


struct NumericKey {
  std::string section, key;  // section "" for the top level
  bool list = false;         // a list of numbers (hidden sizes, action bounds)
};

// The numeric keys of a config, as its writer lists them.
std::vector<NumericKey> NumericKeys(const TrainConfig& config) {
  std::vector<NumericKey> keys;
  const YAML::Node root = YAML::Load(TrainConfigToYaml(config));
  const auto numeric = [](const YAML::Node& node) {
    if (!node.IsScalar()) return false;
    double value = 0;
    const std::string text = node.Scalar();
    return text != "true" && text != "false" && YAML::convert<double>::decode(node, value);
  };
  for (const auto& entry : root) {
    const std::string name = entry.first.Scalar();
    if (entry.second.IsMap()) {
      for (const auto& inner : entry.second) {
        const YAML::Node value = inner.second;
        const bool list = value.IsSequence() && value.size() > 0 && numeric(value[0]);
        if (numeric(value) || list) keys.push_back({name, inner.first.Scalar(), list});
      }
    } else if (numeric(entry.second)) {
      keys.push_back({"", name, false});
    }
  }
  return keys;
}

// `base` with the key set to `value` (a list of that one value, for a list key).
std::string WithValue(const std::string& base, const NumericKey& key, const std::string& value) {
  YAML::Node root = YAML::Load(base);
  const YAML::Node given = YAML::Load(key.list ? "[" + value + "]" : value);
  if (key.section.empty()) {
    root[key.key] = given;
  } else {
    root[key.section][key.key] = given;
  }
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

// Seconds of work for each family: tiny networks, a few steps.
const char* kTinyMpc = R"(task: PointGoal1
seed: 3
training: {pretrain_episodes: 2, pretrain_steps: 20, episodes_per_epoch: 1, total_steps: 60}
ensemble: {hidden_sizes: [8], max_epochs: 2}
classifier: {rounds: 5}
planning: {horizon: 3, population: 12, elites: 3, min_feasible_elites: 2, max_iterations: 2,
           random_samples: 20}
)";
const char* kTinyModelFree = R"(task: PointGoal1
algorithm: trpo-lagrangian
variant: paper-lidar
seed: 3
training: {total_steps: 200}
policy_optimisation: {steps_per_epoch: 100, envs: 1, policy_hidden: [8], value_hidden: [8],
                      value_iterations: 2, cg_iterations: 3, backtrack_iterations: 3}
)";

// Trains the config for its budget (no episode ends in it: the learners' own checks of their
// losses and predictions are what a bad value trips); "" when the run reaches it, otherwise what
// went wrong.
std::string TrainFault(const TrainConfig& config, const std::string& name) {
  const std::string dir = testing::TestTempPath(name);
  std::filesystem::remove_all(dir);
  try {
    ProgressSummary last;
    Trainer::Start(config, dir)->Run([&](const ProgressSummary& unit) { last = unit; });
    std::filesystem::remove_all(dir);
    if (last.steps < last.budget || last.budget == 0) {
      return fmt::format("stopped at step {} of {}", last.steps, last.budget);
    }
    return "";
  } catch (const std::exception& error) {
    return error.what();
  }
}

// 0, -1, NaN, infinity, 1e300 and a string, for every numeric key of both families' configs
// (an MPC and a model-free run: each reads sections the other does not, and must refuse values
// in those too). Refused values must name their key; accepted ones must train.
TEST(EveryKeyTest, EachNumericKeyIsRefusedByNameOrTrains) {
  const std::vector<std::string> values = {"0", "-1", ".nan", ".inf", "1.0e+300", "x"};
  std::vector<std::string> faults;
  int refused = 0, trained = 0;
  for (const std::string& base : {std::string(kTinyMpc), std::string(kTinyModelFree)}) {
    const std::vector<NumericKey> keys = NumericKeys(ParseTrainConfig(base, "base"));
    EXPECT_GT(keys.size(), 60u);
    for (const NumericKey& key : keys) {
      for (const std::string& value : values) {
        const std::string label = fmt::format("{}{}{} = {}", key.section,
                                              key.section.empty() ? "" : ".", key.key, value);
        std::optional<TrainConfig> config;
        try {
          config = ParseTrainConfig(WithValue(base, key, value), "c.yaml");
        } catch (const Error& error) {
          ++refused;
          const std::string message = error.what();
          if (message.find(key.key) == std::string::npos ||
              message.find("expected") == std::string::npos) {
            faults.push_back(label + ": refused without naming the key: " + message);
          }
          continue;
        }
        ++trained;
        const std::string fault = TrainFault(*config, "walk");
        if (!fault.empty()) faults.push_back(label + ": accepted, then failed: " + fault);
      }
    }
  }
  EXPECT_TRUE(faults.empty()) << fmt::format("{}", fmt::join(faults, "\n"));
  EXPECT_GT(refused, 500);
  std::printf("%d values refused by their key, %d accepted and trained\n", refused, trained);
}

}  // namespace
}  // namespace cmbrl

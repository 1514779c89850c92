#include "cmbrl/experiment/config.h"

#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <typeinfo>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/env/tasks/goal_spec.h"
#include "cmbrl/env/variant.h"

namespace cmbrl {
namespace {

template <typename T>
const char* TypeName() {
  if constexpr (std::is_same_v<T, bool>) return "true or false";
  if constexpr (std::is_integral_v<T>) return "an integer";
  if constexpr (std::is_floating_point_v<T>) return "a number";
  if constexpr (std::is_same_v<T, std::string>) return "a string";
  return "a list of integers";
}

// One mapping of the file: reads known keys into fields and reports the ones nobody read.
class Section {
 public:
  Section(const YAML::Node& node, std::string path, const std::string& source)
      : node_(node), path_(std::move(path)), source_(source) {
    Require(!node_.IsDefined() || node_.IsNull() || node_.IsMap(),
            "config '{}': '{}' must be a mapping of keys to values", source_, Name(""));
  }

  std::string Name(const std::string& key) const {
    return path_.empty() ? key : key.empty() ? path_ : path_ + "." + key;
  }

  template <typename T>
  void Read(const std::string& key, T& field) {
    known_.push_back(key);
    if (!node_.IsMap() || !node_[key]) return;
    const YAML::Node value = node_[key];
    try {
      field = value.as<T>();
    } catch (const YAML::Exception&) {
      Fail("config '{}': key '{}' is '{}': expected {}", source_, Name(key), Dump(value),
           TypeName<T>());
    }
  }

  Section Child(const std::string& key) {
    known_.push_back(key);
    return Section(node_.IsMap() ? node_[key] : YAML::Node(), Name(key), source_);
  }

  // Throws for any key of the file that no Read or Child asked for.
  void RejectUnknownKeys() const {
    if (!node_.IsMap()) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.as<std::string>();
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        Fail("config '{}': unknown key '{}': expected one of {}", source_, Name(key),
             fmt::join(known_, ", "));
      }
    }
  }

 private:
  static std::string Dump(const YAML::Node& node) {
    YAML::Emitter out;
    out << YAML::Flow << node;
    return out.c_str();
  }

  YAML::Node node_;
  std::string path_;
  const std::string& source_;
  std::vector<std::string> known_;
};

// Reads (or, with a null node, only declares) every key; shared by parsing and the key list.
void MapConfig(Section& root, TrainConfig& c) {
  root.Read("task", c.task);
  root.Read("variant", c.variant);
  root.Read("planner", c.planner);
  root.Read("seed", c.seed);
  root.Read("device", c.device);

  Section training = root.Child("training");
  training.Read("pretrain_episodes", c.training.pretrain_episodes);
  training.Read("pretrain_steps", c.training.pretrain_steps);
  training.Read("episodes_per_epoch", c.training.episodes_per_epoch);
  training.Read("total_steps", c.training.total_steps);
  training.Read("transition_capacity", c.training.transition_capacity);
  training.Read("safe_capacity", c.training.safe_capacity);
  training.Read("unsafe_capacity", c.training.unsafe_capacity);
  training.RejectUnknownKeys();

  Section ensemble = root.Child("ensemble");
  EnsembleOptions& e = c.ensemble;
  ensemble.Read("ensemble_size", e.ensemble_size);
  ensemble.Read("hidden_sizes", e.hidden_sizes);
  ensemble.Read("predict_delta", e.predict_delta);
  ensemble.Read("learning_rate", e.learning_rate);
  ensemble.Read("batch_size", e.batch_size);
  ensemble.Read("max_epochs", e.max_epochs);
  ensemble.Read("validation_fraction", e.validation_fraction);
  ensemble.Read("member_subset_fraction", e.member_subset_fraction);
  ensemble.Read("validate_every", e.validate_every);
  ensemble.Read("patience", e.patience);
  ensemble.Read("init_std", e.init_std);
  ensemble.Read("min_std", e.min_std);
  ensemble.RejectUnknownKeys();

  Section classifier = root.Child("classifier");
  XgbCostModelOptions& x = c.classifier;
  classifier.Read("rounds", x.rounds);
  classifier.Read("learning_rate", x.learning_rate);
  classifier.Read("max_depth", x.max_depth);
  classifier.Read("max_leaves", x.max_leaves);
  classifier.Read("grow_policy", x.grow_policy);
  classifier.Read("tree_method", x.tree_method);
  classifier.Read("l2_regularization", x.l2_regularization);
  classifier.Read("min_child_weight", x.min_child_weight);
  classifier.Read("boost_from_average", x.boost_from_average);
  classifier.Read("threshold", x.threshold);
  classifier.Read("safe_per_unsafe", x.safe_per_unsafe);
  classifier.Read("threads", x.threads);
  classifier.RejectUnknownKeys();

  Section planning = root.Child("planning");
  PlanningProblem& p = c.planning.problem;
  planning.Read("horizon", p.horizon);
  planning.Read("action_low", p.action_low);
  planning.Read("action_high", p.action_high);
  CrossEntropyOptions& ce = c.planning.cross_entropy;
  planning.Read("population", ce.population);
  planning.Read("elites", ce.elites);
  planning.Read("min_feasible_elites", ce.min_feasible_elites);
  planning.Read("max_iterations", ce.max_iterations);
  planning.Read("epsilon", ce.epsilon);
  planning.Read("alpha", ce.alpha);
  planning.Read("initial_variance", ce.initial_variance);
  planning.Read("penalty", ce.penalty);
  planning.Read("warm_start", ce.warm_start);
  planning.Read("random_samples", c.planning.random.samples);
  planning.RejectUnknownKeys();

  Section objective = root.Child("objective");
  TrajectoryObjectiveOptions& o = c.objective;
  objective.Read("goal_index", o.goal_index);
  objective.Read("gamma", o.gamma);
  objective.Read("beta", o.beta);
  objective.Read("near_goal_radius", o.near_goal_radius);
  objective.Read("near_goal_bonus", o.near_goal_bonus);
  objective.Read("at_goal_radius", o.at_goal_radius);
  objective.Read("at_goal_bonus", o.at_goal_bonus);
  objective.RejectUnknownKeys();

  root.RejectUnknownKeys();
  SetTrainDevice(c, c.device);
  c.planning.random.penalty = c.planning.cross_entropy.penalty;  // one penalty for CEM and random
}

// Runs a component's validation and names the section in its message ("planning.elites is ...").
template <typename Check>
void InSection(const std::string& source, const std::string& section, Check&& check) {
  try {
    check();
  } catch (const Error& error) {
    Fail("config '{}': {}.{}", source, section, error.what());
  }
}

}  // namespace

void SetTrainDevice(TrainConfig& c, const std::string& device) {
  c.device = device;
  c.ensemble.device = device;
  c.classifier.device = device;
  c.planning.problem.device = device;
}

TrainConfig ParseTrainConfig(const std::string& yaml, const std::string& source) {
  YAML::Node document;
  try {
    document = YAML::Load(yaml);
  } catch (const YAML::Exception& error) {
    Fail("config '{}' is not valid YAML: {}", source, error.what());
  }
  TrainConfig config;
  Section root(document, "", source);
  MapConfig(root, config);
  ValidateTrainConfig(config, source);
  return config;
}

TrainConfig LoadTrainConfig(const std::string& path) {
  std::ifstream in(path);
  Require(static_cast<bool>(in), "config file '{}' cannot be opened: expected a YAML file", path);
  std::stringstream text;
  text << in.rdbuf();
  return ParseTrainConfig(text.str(), path);
}

void ValidateTrainConfig(const TrainConfig& c, const std::string& source) {
  InSection(source, "task", [&] { GoalTaskSpecByName(c.task, ParseVariant(c.variant)); });
  const std::vector<std::string>& planners = PlannerNames();
  Require(std::find(planners.begin(), planners.end(), c.planner) != planners.end(),
          "config '{}': key 'planner' is '{}': expected one of {}", source, c.planner,
          fmt::join(planners, ", "));
  InSection(source, "device", [&] { ParseDevice(c.device); });
  const TrainingLoopOptions& t = c.training;
  InSection(source, "training", [&] {
    Require(t.pretrain_episodes >= 0, "pretrain_episodes is {}: expected 0 or more",
            t.pretrain_episodes);
    Require(t.pretrain_steps >= 1, "pretrain_steps is {}: expected at least 1", t.pretrain_steps);
    Require(t.episodes_per_epoch >= 1, "episodes_per_epoch is {}: expected at least 1",
            t.episodes_per_epoch);
    Require(t.total_steps >= 1, "total_steps is {}: expected at least 1", t.total_steps);
    Require(t.transition_capacity >= 2, "transition_capacity is {}: expected at least 2",
            t.transition_capacity);
    Require(t.safe_capacity >= 1 && t.unsafe_capacity >= 1,
            "safe_capacity and unsafe_capacity are {} and {}: expected at least 1", t.safe_capacity,
            t.unsafe_capacity);
  });
  InSection(source, "ensemble", [&] { ValidateEnsembleOptions(c.ensemble); });
  InSection(source, "classifier", [&] { ValidateXgbCostModelOptions(c.classifier); });
  InSection(source, "planning", [&] {
    ValidateCrossEntropyOptions(c.planning.cross_entropy);
    ValidateRandomShootingOptions(c.planning.random);
    MakePlanner(c.planner, c.planning, 0);  // the problem's own checks (horizon, bounds)
  });
  // The planning objective reads the goal from the paper's ego-state vector.
  const GoalTaskSpec spec = GoalTaskSpecByName(c.task, ParseVariant(c.variant));
  Require(spec.observation == ObservationKind::kEgoState,
          "config '{}': key 'variant' is '{}': training plans on the paper variant's ego-state "
          "vector (the standard variant observes lidar)",
          source, c.variant);
  InSection(source, "objective",
            [&] { ValidateTrajectoryObjectiveOptions(c.objective, ObservationSize(spec)); });
}

std::string TrainConfigToYaml(const TrainConfig& c) {
  YAML::Emitter out;
  const auto section = [&out](const char* name, auto&& body) {
    out << YAML::Key << name << YAML::Value << YAML::BeginMap;
    body();
    out << YAML::EndMap;
  };
  const auto kv = [&out](const char* key, const auto& value) {
    out << YAML::Key << key << YAML::Value << value;
  };
  out << YAML::BeginMap;
  kv("task", c.task);
  kv("variant", c.variant);
  kv("planner", c.planner);
  kv("seed", c.seed);
  kv("device", c.device);
  section("training", [&] {
    const TrainingLoopOptions& t = c.training;
    kv("pretrain_episodes", t.pretrain_episodes);
    kv("pretrain_steps", t.pretrain_steps);
    kv("episodes_per_epoch", t.episodes_per_epoch);
    kv("total_steps", t.total_steps);
    kv("transition_capacity", t.transition_capacity);
    kv("safe_capacity", t.safe_capacity);
    kv("unsafe_capacity", t.unsafe_capacity);
  });
  section("ensemble", [&] {
    const EnsembleOptions& e = c.ensemble;
    kv("ensemble_size", e.ensemble_size);
    out << YAML::Key << "hidden_sizes" << YAML::Value << YAML::Flow << e.hidden_sizes;
    kv("predict_delta", e.predict_delta);
    kv("learning_rate", e.learning_rate);
    kv("batch_size", e.batch_size);
    kv("max_epochs", e.max_epochs);
    kv("validation_fraction", e.validation_fraction);
    kv("member_subset_fraction", e.member_subset_fraction);
    kv("validate_every", e.validate_every);
    kv("patience", e.patience);
    kv("init_std", e.init_std);
    kv("min_std", e.min_std);
  });
  section("classifier", [&] {
    const XgbCostModelOptions& x = c.classifier;
    kv("rounds", x.rounds);
    kv("learning_rate", x.learning_rate);
    kv("max_depth", x.max_depth);
    kv("max_leaves", x.max_leaves);
    kv("grow_policy", x.grow_policy);
    kv("tree_method", x.tree_method);
    kv("l2_regularization", x.l2_regularization);
    kv("min_child_weight", x.min_child_weight);
    kv("boost_from_average", x.boost_from_average);
    kv("threshold", x.threshold);
    kv("safe_per_unsafe", x.safe_per_unsafe);
    kv("threads", x.threads);
  });
  section("planning", [&] {
    const PlanningProblem& p = c.planning.problem;
    const CrossEntropyOptions& ce = c.planning.cross_entropy;
    kv("horizon", p.horizon);
    kv("action_low", p.action_low);
    kv("action_high", p.action_high);
    kv("population", ce.population);
    kv("elites", ce.elites);
    kv("min_feasible_elites", ce.min_feasible_elites);
    kv("max_iterations", ce.max_iterations);
    kv("epsilon", ce.epsilon);
    kv("alpha", ce.alpha);
    kv("initial_variance", ce.initial_variance);
    kv("penalty", ce.penalty);
    kv("warm_start", ce.warm_start);
    kv("random_samples", c.planning.random.samples);
  });
  section("objective", [&] {
    const TrajectoryObjectiveOptions& o = c.objective;
    kv("goal_index", o.goal_index);
    kv("gamma", o.gamma);
    kv("beta", o.beta);
    kv("near_goal_radius", o.near_goal_radius);
    kv("near_goal_bonus", o.near_goal_bonus);
    kv("at_goal_radius", o.at_goal_radius);
    kv("at_goal_bonus", o.at_goal_bonus);
  });
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace cmbrl

#include "cmbrl/config/config.h"

#include <fmt/ranges.h>
#include <unistd.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <typeinfo>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"
#include "cmbrl/core/memory.h"
#include "cmbrl/core/device_name.h"
#include "cmbrl/env/tasks/task_spec.h"
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
    if constexpr (!std::is_same_v<T, std::string> && !std::is_same_v<T, std::vector<std::string>>) {
      // A quoted value is a string, whatever it spells ('24', "true"): YAML's and JSON's rule.
      const auto quoted = [](const YAML::Node& node) {
        return node.IsScalar() && node.Tag() == "!";
      };
      bool any = quoted(value);
      if (value.IsSequence()) {
        for (const YAML::Node& item : value) any = any || quoted(item);
      }
      if (any) {
        Fail("config '{}': key '{}' is '{}', a string: expected {} (write it without quotes)",
             source_, Name(key), Dump(value), TypeName<T>());
      }
    }
    try {
      field = value.as<T>();
    } catch (const YAML::Exception&) {
      if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
        // A number that is not an integer of this range (1e12, 2.5, -1 for an unsigned key).
        double number = 0.0;
        if (YAML::convert<double>::decode(value, number)) {
          Fail("config '{}': key '{}' is '{}': expected an integer from {} to {}", source_,
               Name(key), Dump(value), std::numeric_limits<T>::min(),
               std::numeric_limits<T>::max());
        }
      }
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
        Fail("config '{}': unknown key '{}'{}: expected one of {}", source_, Name(key),
             DidYouMean(key, known_, path_.empty() ? "" : path_ + "."), fmt::join(known_, ", "));
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

// Every key of the file, once: section ("" for the top level), key and field. Reading and
// writing both walk this list, so they cannot drift apart. Keys of one section stay together.
template <typename Config, typename Visitor>
void VisitConfig(Config& c, Visitor& v) {
  v.Field("", "task", c.task);
  v.Field("", "variant", c.variant);
  v.Field("", "algorithm", c.algorithm);
  v.Field("", "planner", c.planner);
  v.Field("", "seed", c.seed);
  v.Field("", "device", c.device);
  v.Field("environment", "spawn", c.spawn);
  v.Field("environment", "previous_action", c.previous_action);
  v.Field("environment", "observation_size", c.observation_size);
  v.Field("environment", "action_size", c.action_size);
  auto& d = c.mujoco_task;
  v.Field("mujoco_task", "model", d.model);
  v.Field("mujoco_task", "sensors", d.sensors);
  v.Field("mujoco_task", "lidar_body", d.lidar_body);
  v.Field("mujoco_task", "lidar_groups", d.lidar_groups);
  v.Field("mujoco_task", "lidar_bins", d.lidar_bins);
  v.Field("mujoco_task", "lidar_max_dist", d.lidar_max_dist);
  v.Field("mujoco_task", "cost_geoms", d.cost_geoms);
  v.Field("mujoco_task", "cost_contact_with", d.cost_contact_with);
  v.Field("mujoco_task", "cost_site", d.cost_site);
  v.Field("mujoco_task", "cost_regions", d.cost_regions);
  v.Field("mujoco_task", "reward", d.reward);
  v.Field("mujoco_task", "reward_sensor", d.reward_sensor);
  v.Field("mujoco_task", "reward_target", d.reward_target);
  v.Field("mujoco_task", "reward_axis", d.reward_axis);
  v.Field("mujoco_task", "episode_steps", d.episode_steps);
  v.Field("mujoco_task", "action_repeat", d.action_repeat);
  v.Field("mujoco_task", "reset_joints", d.reset_joints);
  v.Field("mujoco_task", "reset_low", d.reset_low);
  v.Field("mujoco_task", "reset_high", d.reset_high);
  auto& py = c.python;
  v.Field("python", "env", py.env);
  v.Field("python", "reward", py.reward);
  v.Field("python", "termination", py.termination);
  v.Field("python", "path", py.path);
  auto& t = c.training;
  v.Field("training", "pretrain_episodes", t.pretrain_episodes);
  v.Field("training", "pretrain_steps", t.pretrain_steps);
  v.Field("training", "episodes_per_epoch", t.episodes_per_epoch);
  v.Field("training", "total_steps", t.total_steps);
  v.Field("training", "transition_capacity", t.transition_capacity);
  v.Field("training", "safe_capacity", t.safe_capacity);
  v.Field("training", "unsafe_capacity", t.unsafe_capacity);
  v.Field("training", "label_every_step", t.label_every_step);
  auto& e = c.ensemble;
  v.Field("ensemble", "ensemble_size", e.ensemble_size);
  v.Field("ensemble", "hidden_sizes", e.hidden_sizes);
  v.Field("ensemble", "predict_delta", e.predict_delta);
  v.Field("ensemble", "learning_rate", e.learning_rate);
  v.Field("ensemble", "batch_size", e.batch_size);
  v.Field("ensemble", "max_epochs", e.max_epochs);
  v.Field("ensemble", "validation_fraction", e.validation_fraction);
  v.Field("ensemble", "member_subset_fraction", e.member_subset_fraction);
  v.Field("ensemble", "validate_every", e.validate_every);
  v.Field("ensemble", "patience", e.patience);
  v.Field("ensemble", "init_std", e.init_std);
  v.Field("ensemble", "min_std", e.min_std);
  v.Field("ensemble", "precision", e.precision);
  v.Field("ensemble", "backend", e.backend);
  auto& x = c.classifier;
  v.Field("classifier", "rounds", x.rounds);
  v.Field("classifier", "learning_rate", x.learning_rate);
  v.Field("classifier", "max_depth", x.max_depth);
  v.Field("classifier", "max_leaves", x.max_leaves);
  v.Field("classifier", "grow_policy", x.grow_policy);
  v.Field("classifier", "tree_method", x.tree_method);
  v.Field("classifier", "l2_regularization", x.l2_regularization);
  v.Field("classifier", "min_child_weight", x.min_child_weight);
  v.Field("classifier", "boost_from_average", x.boost_from_average);
  v.Field("classifier", "threshold", x.threshold);
  v.Field("classifier", "safe_per_unsafe", x.safe_per_unsafe);
  v.Field("classifier", "safe_selection", x.safe_selection);
  v.Field("classifier", "threads", x.threads);
  v.Field("classifier", "predict_threads", x.predict_threads);
  auto& p = c.planning.problem;
  auto& ce = c.planning.cross_entropy;
  v.Field("planning", "horizon", p.horizon);
  v.Field("planning", "action_low", p.action_low);
  v.Field("planning", "action_high", p.action_high);
  v.Field("planning", "population", ce.population);
  v.Field("planning", "elites", ce.elites);
  v.Field("planning", "min_feasible_elites", ce.min_feasible_elites);
  v.Field("planning", "max_iterations", ce.max_iterations);
  v.Field("planning", "epsilon", ce.epsilon);
  v.Field("planning", "alpha", ce.alpha);
  v.Field("planning", "initial_variance", ce.initial_variance);
  v.Field("planning", "penalty", c.planning.penalty);
  v.Field("planning", "warm_start", ce.warm_start);
  v.Field("planning", "random_samples", c.planning.random.samples);
  auto& economy = c.planning.economy;
  v.Field("planning", "population_decay", economy.population_decay);
  v.Field("planning", "keep_elites", economy.keep_elites);
  v.Field("planning", "noise_exponent", economy.noise_exponent);
  auto& o = c.objective;
  v.Field("objective", "reward", o.reward);
  v.Field("objective", "termination", o.termination);
  v.Field("objective", "analytic_form", o.analytic_form);
  v.Field("objective", "goal_index", o.goal_index);
  v.Field("objective", "gamma", o.gamma);
  v.Field("objective", "beta", o.beta);
  v.Field("objective", "near_goal_radius", o.near_goal_radius);
  v.Field("objective", "near_goal_bonus", o.near_goal_bonus);
  v.Field("objective", "at_goal_radius", o.at_goal_radius);
  v.Field("objective", "at_goal_bonus", o.at_goal_bonus);
  v.Field("objective", "at_goal_test_after_near_bonus", o.at_goal_test_after_near_bonus);
  for (auto [section, r] : {std::pair{"reward_model", &c.reward_model},
                             std::pair{"termination_model", &c.termination_model}}) {
    v.Field(section, "hidden_sizes", r->hidden_sizes);
    v.Field(section, "learning_rate", r->learning_rate);
    v.Field(section, "batch_size", r->batch_size);
    v.Field(section, "max_epochs", r->max_epochs);
    v.Field(section, "validation_fraction", r->validation_fraction);
    v.Field(section, "patience", r->patience);
  }
  auto& m = c.policy_optimisation;
  v.Field("policy_optimisation", "steps_per_epoch", m.steps_per_epoch);
  v.Field("policy_optimisation", "envs", m.envs);
  v.Field("policy_optimisation", "env_threads", m.env_threads);
  v.Field("policy_optimisation", "policy_hidden", m.policy_hidden);
  v.Field("policy_optimisation", "initial_log_std", m.initial_log_std);
  v.Field("policy_optimisation", "value_hidden", m.value_hidden);
  v.Field("policy_optimisation", "value_learning_rate", m.value_learning_rate);
  v.Field("policy_optimisation", "value_iterations", m.value_iterations);
  v.Field("policy_optimisation", "gamma", m.gamma);
  v.Field("policy_optimisation", "lambda", m.lambda);
  v.Field("policy_optimisation", "target_kl", m.target_kl);
  v.Field("policy_optimisation", "damping", m.damping);
  v.Field("policy_optimisation", "cg_iterations", m.cg_iterations);
  v.Field("policy_optimisation", "backtrack_coefficient", m.backtrack_coefficient);
  v.Field("policy_optimisation", "backtrack_iterations", m.backtrack_iterations);
  v.Field("policy_optimisation", "cost_limit", m.cost_limit);
  v.Field("policy_optimisation", "penalty_init", m.penalty_init);
  v.Field("policy_optimisation", "penalty_learning_rate", m.penalty_learning_rate);
  v.Field("policy_optimisation", "policy_learning_rate", m.policy_learning_rate);
  v.Field("policy_optimisation", "policy_iterations", m.policy_iterations);
  v.Field("policy_optimisation", "clip_ratio", m.clip_ratio);
  v.Field("policy_optimisation", "kl_margin", m.kl_margin);
}

// Reads the fields that the file names; then refuses any key it does not know.
class ConfigReader {
 public:
  ConfigReader(const YAML::Node& document, const std::string& source)
      : root_(document, "", source), source_(source) {}

  template <typename T>
  void Field(const std::string& section, const char* key, T& value) {
    SectionFor(section).Read(key, value);
  }

  // Named choices (variant, spawn) are parsed here, once; a bad one is named under its key.
  void Field(const std::string& section, const char* key, Variant& value) {
    ReadChoice(section, key, value, VariantName, ParseVariant);
  }
  void Field(const std::string& section, const char* key, Spawn& value) {
    ReadChoice(section, key, value, SpawnName, ParseSpawn);
  }

  void RejectUnknownKeys() const {
    for (const auto& [name, section] : sections_) section.RejectUnknownKeys();
    root_.RejectUnknownKeys();
  }

 private:
  template <typename Choice>
  void ReadChoice(const std::string& section, const char* key, Choice& value,
                  std::string (*name_of)(Choice), Choice (*parse)(const std::string&)) {
    std::string name = name_of(value);
    SectionFor(section).Read(key, name);
    try {
      value = parse(name);
    } catch (const Error& error) {
      const std::string where =
          section.empty() ? fmt::format("key '{}'", key) : fmt::format("{}.{}", section, key);
      Fail("config '{}': {}: {}", source_, where, error.what());
    }
  }

  Section& SectionFor(const std::string& name) {
    if (name.empty()) return root_;
    auto found = sections_.find(name);
    if (found == sections_.end()) found = sections_.emplace(name, root_.Child(name)).first;
    return found->second;
  }

  Section root_;
  const std::string& source_;
  std::map<std::string, Section> sections_;
};

// Writes every field, one YAML mapping per section.
class ConfigWriter {
 public:
  ConfigWriter() { out_ << YAML::BeginMap; }

  template <typename T>
  void Field(const std::string& section, const char* key, const T& value) {
    if (section != open_section_) {
      if (!open_section_.empty()) out_ << YAML::EndMap;
      if (!section.empty()) out_ << YAML::Key << section << YAML::Value << YAML::BeginMap;
      open_section_ = section;
    }
    out_ << YAML::Key << key << YAML::Value;
    if constexpr (std::is_same_v<T, std::vector<int>> || std::is_same_v<T, std::vector<double>> ||
                  std::is_same_v<T, std::vector<std::string>>) {
      out_ << YAML::Flow;
    }
    if constexpr (std::is_same_v<T, Variant>) {
      out_ << VariantName(value);
    } else if constexpr (std::is_same_v<T, Spawn>) {
      out_ << SpawnName(value);
    } else {
      out_ << value;
    }
  }

  std::string Finish() {
    if (!open_section_.empty()) out_ << YAML::EndMap;
    out_ << YAML::EndMap;
    return std::string(out_.c_str()) + "\n";
  }

 private:
  YAML::Emitter out_;
  std::string open_section_;
};

// Whether `task` can name a task of one's own (a task file's, a Python environment's given a
// name): not empty, not a built-in task's, not "python:...".
bool IsOwnTaskName(const std::string& task) {
  const std::vector<std::string> built_in = EnvNames();
  return !task.empty() && !IsPythonTask(task) &&
         std::find(built_in.begin(), built_in.end(), task) == built_in.end();
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

// The same for a top-level key ("key 'task': unknown task ...").
template <typename Check>
void AtKey(const std::string& source, const std::string& key, Check&& check) {
  try {
    check();
  } catch (const Error& error) {
    Fail("config '{}': key '{}': {}", source, key, error.what());
  }
}

// Refuses what YAML accepts but a config cannot mean: several documents in one file, a document
// that is empty or not a mapping, and a key given twice in one mapping (YAML keeps only one of
// them, silently). Names the file and the line (1-based).
// A config's bounds, checked before it is read as a whole: its size, and (by the parser's events,
// which cost one pass over the text) no anchors or aliases (an alias "bomb" expands exponentially
// when read), no tags that change a value's type (!!str 24), and a limited nesting depth.
constexpr std::size_t kMaxConfigBytes = 1 << 20;
constexpr int kMaxConfigDepth = 16;

class BoundedYaml final : public YAML::EventHandler {
 public:
  explicit BoundedYaml(const std::string& source) : source_(source) {}
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { Check(mark, anchor, ""); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    Fail("config '{}', line {}: YAML aliases (*name) are not accepted: write the value out",
         source_, mark.line + 1);
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string&) override {
    Check(mark, anchor, tag);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    Open(mark, anchor, tag);
  }
  void OnSequenceEnd() override { --depth_; }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    Open(mark, anchor, tag);
  }
  void OnMapEnd() override { --depth_; }

 private:
  void Check(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string& tag) const {
    Require(anchor == 0,
            "config '{}', line {}: YAML anchors (&name) are not accepted: write each value out",
            source_, mark.line + 1);
    Require(tag.empty() || tag == "?" || tag == "!",
            "config '{}', line {}: the YAML tag '{}' is not accepted: a value's type is the "
            "key's (write 24, not !!str 24)",
            source_, mark.line + 1, tag);
  }
  void Open(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string& tag) {
    Check(mark, anchor, tag);
    Require(++depth_ <= kMaxConfigDepth,
            "config '{}', line {}: nested more than {} levels deep: a config is sections of keys",
            source_, mark.line + 1, kMaxConfigDepth);
  }

  const std::string& source_;
  int depth_ = 0;
};

// Throws cmbrl::Error naming `source` for YAML text beyond BoundedYaml's bounds; YAML's own
// exception for text that is not YAML.
void RequireBoundedYaml(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  BoundedYaml bounds(source);
  while (parser.HandleNextDocument(bounds)) {
  }
}

YAML::Node LoadConfigDocument(const std::string& text, const std::string& source) {
  Require(text.size() <= kMaxConfigBytes,
          "config '{}' is {} bytes: a config is at most {} bytes (1 MiB)", source, text.size(),
          kMaxConfigBytes);
  try {
    RequireBoundedYaml(text, source);
  } catch (const YAML::Exception& error) {
    Fail("config '{}' is not valid YAML: {}", source, error.what());
  }
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(text);
  } catch (const YAML::Exception& error) {
    Fail("config '{}' is not valid YAML: {}", source, error.what());
  }
  Require(documents.size() <= 1,
          "config '{}' holds {} YAML documents (separated by '---'): expected one", source,
          documents.size());
  Require(!documents.empty() && !documents.front().IsNull(),
          "config '{}' is empty: expected a mapping of keys to values (task: PointGoal1, ...)",
          source);
  const YAML::Node& document = documents.front();
  Require(document.IsMap(), "config '{}', line {}: the document is not a mapping of keys to "
          "values", source, document.Mark().line + 1);
  // Every mapping, at any depth: a repeated key is an error.
  std::vector<YAML::Node> pending = {document};
  while (!pending.empty()) {
    const YAML::Node node = pending.back();
    pending.pop_back();
    if (node.IsMap()) {
      std::set<std::string> keys;
      for (const auto& entry : node) {
        const std::string key = entry.first.Scalar();
        Require(keys.insert(key).second, "config '{}', line {}: key '{}' is given twice",
                source, entry.first.Mark().line + 1, key);
        // A bare "planning:" would replace the whole section of the files before it.
        Require(!entry.second.IsNull(),
                "config '{}', line {}: key '{}' has no value: give it one (a section its keys), "
                "or leave it out",
                source, entry.first.Mark().line + 1, key);
        pending.push_back(entry.second);
      }
    } else if (node.IsSequence()) {
      for (const auto& item : node) pending.push_back(item);
    }
  }
  return document;
}

// LoadConfigDocument of a file's text.
YAML::Node LoadConfigFile(const std::string& path) {
  // Only a regular file of bounded size is read: not a FIFO (which blocks), a device (which may
  // never end) or a folder.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  Require(!error || error == std::errc::no_such_file_or_directory,
          "config file '{}' cannot be read: {}", path, error.message());
  Require(std::filesystem::exists(status), "config file '{}' does not exist: expected a YAML file",
          path);
  Require(std::filesystem::is_regular_file(status),
          "config file '{}' is not a regular file (a folder, a FIFO or a device): expected a "
          "YAML file",
          path);
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  Require(!error && size <= kMaxConfigBytes,
          "config file '{}' is {} bytes: a config is at most {} bytes (1 MiB)", path, size,
          kMaxConfigBytes);
  std::ifstream in(path, std::ios::binary);
  Require(static_cast<bool>(in), "config file '{}' cannot be opened: expected a YAML file", path);
  std::string text(kMaxConfigBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));  // a file grown since is still bounded
  return LoadConfigDocument(text, path);
}

// Merges `overlay` into `base`, key by key: a mapping merges into a mapping (a file or an
// override names only the keys it changes), anything else replaces the value.
void MergeInto(YAML::Node base, const YAML::Node& overlay) {
  for (const auto& entry : overlay) {
    const std::string key = entry.first.as<std::string>();
    YAML::Node current = base[key];
    if (entry.second.IsMap() && current.IsMap()) {
      MergeInto(current, entry.second);
    } else {
      base[key] = YAML::Clone(entry.second);
    }
  }
}

// A config that declares Python parts (section python) names its task and planning functions
// by them: the task DeclaredEnvTask(python.env) (a file that names another task is
// refused), objective.reward python where python.reward is declared and the reward left
// analytic, and objective.termination python likewise (a learned one with a declared function
// is refused).
void ApplyDeclaredPython(const YAML::Node& document, TrainConfig& c, const std::string& source) {
  InSection(source, "python", [&] { ValidatePythonSourceOptions(c.python); });
  if (!c.python.env.empty()) {
    // A name of its own where the file gives one (a sweep's task), else what made it.
    const std::string made = DeclaredEnvTask(c.python.env);
    if (!document["task"]) c.task = made;
    Require(c.task == made || IsOwnTaskName(c.task),
            "config '{}': key 'task' is '{}' with python.env '{}' declared: expected a name of "
            "its own (not a built-in task's, not python:...), or no task (it is then '{}')",
            source, c.task, c.python.env, made);
  }
  // objective.<key> becomes python where python.<key> is declared and it is left at its default.
  const auto plan_with = [&](const char* key, const std::string& declared, std::string& objective,
                             const char* fallback) {
    if (declared.empty()) return;
    Require(objective == fallback || objective == "python",
            "config '{}': key 'objective.{}' is '{}' with python.{} '{}' declared: leave one out",
            source, key, objective, key, declared);
    objective = "python";
  };
  plan_with("reward", c.python.reward, c.objective.reward, "analytic");
  plan_with("termination", c.python.termination, c.objective.termination, "none");
}

}  // namespace

void SetTrainDevice(TrainConfig& c, const std::string& device) {
  c.device = device;
  c.ensemble.device = device;
  c.classifier.device = device;
  c.planning.problem.device = device;
}

namespace {

// The config of a document already read and checked (LoadConfigDocument, per file). Read from
// the nodes themselves, never from text emitted again: emitting loses a value's quotes, and a
// quoted '24' must stay a string.
TrainConfig ParseTrainConfigDocument(const YAML::Node& document, const std::string& source) {
  TrainConfig config;
  ConfigReader reader(document, source);
  VisitConfig(config, reader);
  reader.RejectUnknownKeys();
  // A built-in task the paper did not run exists in the stock variant only: that is its default.
  if (!(document.IsMap() && document["variant"])) {
    const std::vector<TaskEntry>& tasks = Tasks();
    const auto task = std::find_if(tasks.begin(), tasks.end(),
                                   [&](const TaskEntry& t) { return t.name == config.task; });
    if (task != tasks.end()) config.variant = DefaultVariant(*task);
  }
  SetTrainDevice(config, config.device);  // one device for everything
  ApplyDeclaredPython(document, config, source);
  ValidateTrainConfig(config, source);
  return config;
}

}  // namespace

TrainConfig ParseTrainConfig(const std::string& yaml, const std::string& source) {
  return ParseTrainConfigDocument(LoadConfigDocument(yaml, source), source);
}

TrainConfig LoadTrainConfig(const std::string& path) {
  return LoadTrainConfig(std::vector<std::string>{path});
}

bool ConfigFilesNameKey(const std::vector<std::string>& paths, const std::string& key) {
  for (const std::string& path : paths) {
    if (LoadConfigFile(path)[key]) return true;
  }
  return false;
}

namespace {

// A declared task's model path, relative in the file that names it, is taken from that file's
// folder: the run's config.yaml then names it absolute and resumes from anywhere.
YAML::Node WithModelFromFileFolder(YAML::Node document, const std::string& path) {
  const std::filesystem::path folder = std::filesystem::absolute(path).parent_path();
  // Likewise python.path's folders.
  if (document.IsMap() && document["python"].IsMap() && document["python"]["path"].IsSequence()) {
    YAML::Node folders = document["python"]["path"];
    for (size_t i = 0; i < folders.size(); ++i) {
      if (!folders[i].IsScalar() || folders[i].Scalar().empty()) continue;  // refused when read
      const std::filesystem::path given(folders[i].Scalar());
      if (!given.is_relative()) continue;
      std::filesystem::path resolved = (folder / given).lexically_normal();
      if (!resolved.has_filename()) resolved = resolved.parent_path();  // "a/." is "a", not "a/"
      folders[i] = resolved.string();
    }
  }
  if (!document.IsMap() || !document["mujoco_task"].IsMap()) return document;
  YAML::Node model = document["mujoco_task"]["model"];
  if (!model.IsScalar() || model.Scalar().empty()) return document;
  const std::filesystem::path given(model.Scalar());
  if (given.is_relative()) {
    document["mujoco_task"]["model"] =
        (folder / given).lexically_normal().string();
  }
  return document;
}

}  // namespace

TrainConfig LoadTrainConfig(const std::vector<std::string>& paths) {
  Require(!paths.empty(), "no config file given: expected at least one YAML file");
  YAML::Node merged(YAML::NodeType::Map);
  for (const std::string& path : paths) {
    MergeInto(merged, WithModelFromFileFolder(LoadConfigFile(path), path));
  }
  return ParseTrainConfigDocument(merged, fmt::format("{}", fmt::join(paths, "' + '")));
}

namespace {

// The objective a run that plans reads: the ego-state the goal distance reads, the objective's
// options and the task's analytic reward form.
void ValidatePlanningObjective(const TrainConfig& c, int observation_size,
                               const std::string& source) {
  if (IsPythonEnvTask(c)) {
    Require(c.objective.reward != "analytic" || !c.objective.analytic_form.empty(),
            "config '{}': key 'objective.reward' is 'analytic', but task '{}' is an environment "
            "given from Python, which has no analytic reward of its own: give a reward function "
            "(cmbrl.train(..., reward=f)), learn one (objective.reward: learned) or name a form "
            "(objective.analytic_form: one of {})",
            source, c.task, fmt::join(AnalyticRewardNames(), ", "));
  } else if (IsDeclaredTask(c.mujoco_task)) {
    Require(c.objective.analytic_form.empty(),
            "config '{}': key 'objective.analytic_form' is '{}': a declared task plans with its "
            "own reward (mujoco_task.reward)",
            source, c.objective.analytic_form);
  } else if (c.objective.reward == "analytic" && AnalyticRewardForm(c) == kGoalDistanceReward) {
    // The Goal tasks' analytic reward reads the goal from the paper's ego-state vector.
    Require(c.variant == Variant::kPaper,
            "config '{}': key 'variant' is '{}': the goal-distance reward plans on the paper "
            "variant's ego-state vector (the {} variant observes lidar: plan with "
            "objective.analytic_form: {})",
            source, VariantName(c.variant), VariantName(c.variant), kGoalLidarDistanceReward);
  } else if (c.objective.reward == "analytic") {
    // The lidar forms read a lidar observation (planning/reward_term.h).
    Require(c.variant != Variant::kPaper,
            "config '{}': the analytic reward '{}' reads a lidar observation: key 'variant' is "
            "'paper', whose observation is the ego-state vector (expected standard or "
            "paper-lidar)",
            source, AnalyticRewardForm(c));
  }
  if (c.objective.reward == "analytic" && !IsDeclaredTask(c.mujoco_task)) {
    const std::vector<std::string> forms = AnalyticRewardNames();
    const std::string form = AnalyticRewardForm(c);
    Require(std::find(forms.begin(), forms.end(), form) != forms.end(),
            "config '{}': the analytic reward of task '{}' is '{}'{} (objective.analytic_form, "
            "or the task's own): expected one of {}",
            source, c.task, form, DidYouMean(form, forms), fmt::join(forms, ", "));
  }
  InSection(source, "objective",
            [&] { ValidateTrajectoryObjectiveOptions(c.objective, observation_size); });
}

// The mujoco_task keys declare a task of one's own: without its model they would be read and
// ignored, so any of them that differs from its default is refused by name.
void RefuseUndeclaredTaskKeys(const TrainConfig& c, const std::string& source) {
  for (const ConfigDifference& difference : ConfigDifferences(c, TrainConfig{})) {
    Require(difference.key.rfind("mujoco_task.", 0) != 0,
            "config '{}': key '{}' is {}, but no mujoco_task.model is declared: expected no "
            "value (the mujoco_task keys describe a task of one's own, with its model)",
            source, difference.key, difference.ours);
  }
}

// The task's observation size: its spec's for a built-in task, the recorded one for a Python
// environment's (cmbrl.train(env=...) writes environment.observation_size and action_size); 0
// for a declared task's, which only its model tells (its environment checks the rest).
int ValidatedObservationSize(const TrainConfig& c, const std::string& source) {
  if (IsDeclaredTask(c.mujoco_task)) {
    Require(c.python.env.empty(),
            "config '{}': keys 'mujoco_task.model' and 'python.env' are both set: a task is "
            "declared as a MuJoCo model or made by Python, not both",
            source);
    Require(IsOwnTaskName(c.task),
            "config '{}': key 'task' is '{}' with a mujoco_task declared: expected a name of its "
            "own (not a built-in task's, not python:...)",
            source, c.task);
    InSection(source, "mujoco_task", [&] { ValidateMujocoTaskOptions(c.mujoco_task); });
    return 0;
  }
  RefuseUndeclaredTaskKeys(c, source);
  if (IsPythonEnvTask(c)) {
    Require(!IsPythonTask(c.task) || c.task.size() > std::string(kPythonTaskPrefix).size(),
            "config '{}': key 'task' is '{}': expected what made the environment after '{}'",
            source, c.task, kPythonTaskPrefix);
    // A declared environment's sizes are recorded once it is made (Trainer::Start).
    if (!c.python.env.empty() && c.observation_size == 0 && c.action_size == 0) return 0;
    Require(c.observation_size >= 1 && c.observation_size <= 1'000'000 && c.action_size >= 1 &&
                c.action_size <= 10'000,
            "config '{}': keys 'environment.observation_size' and 'environment.action_size' are "
            "{} and {}: a Python environment's run records its sizes (1 to 1000000 and 1 to "
            "10000)",
            source, c.observation_size, c.action_size);
    return c.observation_size;
  }
  Require(c.observation_size == 0 && c.action_size == 0,
          "config '{}': keys 'environment.observation_size' and 'environment.action_size' are {} "
          "and {}: they are a Python environment's, and task '{}' is built in (expected 0)",
          source, c.observation_size, c.action_size, c.task);
  int size = 0;
  AtKey(source, "task", [&] { size = ObservationSize(NavigationTaskSpecByName(c.task, c.variant)); });
  return size;
}

}  // namespace

void ValidateTrainConfig(const TrainConfig& c, const std::string& source) {
  // A built-in robot takes 2 actions; a Python environment's run records its own number.
  const int action_size = IsPythonEnvTask(c) ? c.action_size : 2;
  int observation_size = ValidatedObservationSize(c, source);
  if (c.previous_action && observation_size > 0) observation_size += action_size;
  const std::vector<std::string>& algorithms = AlgorithmNames();
  Require(std::find(algorithms.begin(), algorithms.end(), c.algorithm) != algorithms.end(),
          "config '{}': key 'algorithm' is '{}'{}: expected one of {}", source, c.algorithm,
          DidYouMean(c.algorithm, algorithms), fmt::join(algorithms, ", "));
  InSection(source, "policy_optimisation",
            [&] { ValidatePolicyOptimisationOptions(c.policy_optimisation); });
  Require(FindPlannerInfoOrNull(c.planner) != nullptr,
          "config '{}': key 'planner' is '{}'{}: expected one of {}", source, c.planner,
          DidYouMean(c.planner, PlannerNames()), fmt::join(PlannerNames(), ", "));
  AtKey(source, "device", [&] { CheckDeviceName(c.device); });
  const TrainingLoopOptions& t = c.training;
  InSection(source, "training", [&] {
    // MPC fits its first models on the random episodes: it needs at least one.
    const int least = c.algorithm == "mpc" ? 1 : 0;
    Require(t.pretrain_episodes >= least && t.pretrain_episodes <= 10'000'000,
            "pretrain_episodes is {}: expected {} to 10000000{}", t.pretrain_episodes, least,
            least == 1 ? " (the first models are fitted on these random episodes)" : "");
    Require(t.pretrain_steps >= 1 && t.pretrain_steps <= 1'000'000,
            "pretrain_steps is {}: expected 1 to 1000000", t.pretrain_steps);
    Require(t.episodes_per_epoch >= 1 && t.episodes_per_epoch <= 1'000'000,
            "episodes_per_epoch is {}: expected 1 to 1000000", t.episodes_per_epoch);
    Require(t.total_steps >= 1 && t.total_steps <= kMaxTotalSteps,
            "total_steps is {}: expected 1 to {}", t.total_steps, kMaxTotalSteps);
    Require(t.transition_capacity >= 2 && t.transition_capacity <= 100'000'000,
            "transition_capacity is {}: expected 2 to 100000000", t.transition_capacity);
    Require(t.safe_capacity >= 1 && t.unsafe_capacity >= 1 && t.safe_capacity <= 100'000'000 &&
                t.unsafe_capacity <= 100'000'000,
            "safe_capacity and unsafe_capacity are {} and {}: expected 1 to 100000000 each",
            t.safe_capacity, t.unsafe_capacity);
  });
  InSection(source, "ensemble", [&] { ValidateEnsembleOptions(c.ensemble); });
  InSection(source, "classifier", [&] { ValidateXgbCostModelOptions(c.classifier); });
  InSection(source, "reward_model", [&] { ValidateStepModelOptions(c.reward_model); });
  InSection(source, "termination_model", [&] { ValidateStepModelOptions(c.termination_model); });
  InSection(source, "planning", [&] {
    ValidatePenalty(c.planning.penalty);
    ValidateCrossEntropyOptions(c.planning.cross_entropy);
    ValidateRandomShootingOptions(c.planning.random);
    ValidateSampleEconomyOptions(c.planning.economy);
    ValidatePlanningProblem(c.planning.problem);
  });
  const auto check_memory = [&](const RunMemory& memory) {
    // What the run will hold in memory, before it takes any: sizes each within its bound can
    // still add up to more than the machine has.
    const double available = static_cast<double>(PhysicalMemoryBytes());
    Require(available <= 0 || memory.total() <= kPlannedMemoryShare * available,
            "config '{}': the run would need about {:.1f} GiB ({}), more than 80% of this "
            "machine's {:.1f} GiB: lower the sizes named",
            source, memory.total() / kGiB, memory.Describe(), available / kGiB);
  };
  if (FamilyOf(c.algorithm).Reads("objective")) {
    ValidatePlanningObjective(c, observation_size, source);
  } else {  // unread, but a value no run could use is still no one's meaning
    InSection(source, "objective", [&] { ValidateTrajectoryObjectiveOptions(c.objective, 0); });
  }
  check_memory(EstimateRunMemory(c, observation_size, action_size));
}

std::string AnalyticRewardForm(const TrainConfig& c) {
  if (IsDeclaredTask(c.mujoco_task)) return c.mujoco_task.reward;
  return c.objective.analytic_form.empty() ? FindTask(c.task).analytic_reward
                                           : c.objective.analytic_form;
}

RunMemory EstimateRunMemory(const TrainConfig& c, int state_dim, int action_dim) {
  return FamilyOf(c.algorithm)
      .estimate_memory({state_dim, action_dim, c.training, c.ensemble, c.classifier, c.planning,
                        c.policy_optimisation});
}

std::string TrainConfigToYaml(const TrainConfig& c) {
  ConfigWriter writer;
  VisitConfig(c, writer);
  return writer.Finish();
}

std::vector<ConfigDifference> ConfigDifferences(const TrainConfig& ours, const TrainConfig& theirs) {
  // Both written by the one visitor, then compared key by key in its order.
  const YAML::Node a = YAML::Load(TrainConfigToYaml(ours));
  const YAML::Node b = YAML::Load(TrainConfigToYaml(theirs));
  static const std::set<std::string> kNotMethod = {
      "seed", "device", "classifier.threads", "classifier.predict_threads",
      "policy_optimisation.env_threads"};
  // The shortest text that reads back as the value: 0.3, not YAML's 0.29999999999999999.
  const auto text = [](const YAML::Node& node) {
    double number = 0.0;
    if (node.IsScalar() && node.Scalar().find_first_of(".eE") != std::string::npos &&
        YAML::convert<double>::decode(node, number)) {
      return fmt::format("{}", number);
    }
    YAML::Emitter out;
    out << YAML::Flow << node;
    return std::string(out.c_str());
  };
  std::vector<ConfigDifference> differences;
  for (const auto& entry : a) {
    const std::string name = entry.first.as<std::string>();
    if (entry.second.IsMap()) {
      for (const auto& field : entry.second) {
        const std::string key = name + "." + field.first.as<std::string>();
        const std::string mine = text(field.second);
        const std::string other = text(b[name][field.first.as<std::string>()]);
        if (mine != other && kNotMethod.count(key) == 0) differences.push_back({key, mine, other});
      }
    } else {
      const std::string mine = text(entry.second);
      const std::string other = text(b[name]);
      if (mine != other && kNotMethod.count(name) == 0) differences.push_back({name, mine, other});
    }
  }
  return differences;
}

namespace {

// Every key --set can name in a config's document: a top-level key, or section.key.
std::vector<std::string> OverridableKeys(const YAML::Node& document) {
  std::vector<std::string> keys;
  for (const auto& entry : document) {
    const std::string key = entry.first.as<std::string>();
    if (!entry.second.IsMap()) {
      keys.push_back(key);
      continue;
    }
    for (const auto& inner : entry.second) {
      keys.push_back(key + "." + inner.first.as<std::string>());
    }
  }
  return keys;
}

}  // namespace

TrainConfig ApplyConfigOverrides(const TrainConfig& config,
                                 const std::vector<std::string>& overrides,
                                 const std::string& source) {
  YAML::Node document = YAML::Load(TrainConfigToYaml(config));
  for (const std::string& item : overrides) {
    const size_t equals = item.find('=');
    const std::string key = item.substr(0, equals);
    const size_t dot = key.find('.');
    Require(equals != std::string::npos && !key.empty() && equals + 1 < item.size() &&
                (dot == std::string::npos ||
                 (dot > 0 && dot + 1 < key.size() && key.find('.', dot + 1) == std::string::npos)),
            "{} '{}': expected section.key=value, e.g. planning.population=500", source, item);
    const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
    const std::string name = dot == std::string::npos ? key : key.substr(dot + 1);
    const YAML::Node parent = section.empty() ? document : document[section];
    Require(parent.IsMap() && parent[name], "{} '{}': unknown key '{}'{}", source, item, key,
            DidYouMean(key, OverridableKeys(document)));
    YAML::Node value;
    const std::string text = item.substr(equals + 1);
    const std::string where = fmt::format("{} '{}'", source, item);
    try {
      RequireBoundedYaml(text, where);  // no anchors, aliases or type tags; bounded depth
      value = YAML::Load(text);
    } catch (const YAML::Exception& error) {
      Fail("{}: the value is not valid YAML: {}", where, error.what());
    }
    Require(!value.IsNull(), "{}: the value is null: give one", where);
    YAML::Node patch(YAML::NodeType::Map);
    if (section.empty()) {
      patch[name] = value;
    } else {
      patch[section][name] = value;
    }
    MergeInto(document, patch);  // a mapping merges into its section, keeping its other keys
  }
  return ParseTrainConfigDocument(document, source);
}

}  // namespace cmbrl

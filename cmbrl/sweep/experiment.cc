#include "cmbrl/sweep/experiment.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <openssl/evp.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/report/reference.h"
#include "cmbrl/run/run_directory.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

// A YAML scalar or sequence in one line, as `--set` reads it back ("0.3", "[256, 256]").
std::string FlowText(const YAML::Node& node) {
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

template <typename T>
std::vector<T> ListAt(const YAML::Node& document, const std::string& key,
                      const std::string& source) {
  const YAML::Node node = document[key];
  Require(node && node.IsSequence() && node.size() > 0,
          "experiment '{}': key '{}' is {}: expected a non-empty list", source, key,
          node ? fmt::format("'{}'", FlowText(node)) : std::string("missing"));
  std::vector<T> values;
  for (const YAML::Node& item : node) {
    try {
      values.push_back(item.as<T>());
    } catch (const YAML::Exception&) {
      Fail("experiment '{}': key '{}' holds '{}': expected {}", source, key, FlowText(item),
           std::is_same_v<T, std::string> ? "a name" : "a non-negative integer");
    }
  }
  return values;
}

// The overrides of a mapping of "section.key" to a value, in the file's order.
std::vector<std::string> OverridesOf(const YAML::Node& node, const std::string& key,
                                     const std::string& source) {
  if (!node || node.IsNull()) return {};
  Require(node.IsMap(), "experiment '{}': key '{}' is '{}': expected a mapping of config keys "
          "(section.key, as --set takes them) to values", source, key, FlowText(node));
  std::vector<std::string> overrides;
  for (const auto& entry : node) {
    overrides.push_back(entry.first.as<std::string>() + "=" + FlowText(entry.second));
  }
  return overrides;
}

// The `decision` mapping: `rule: equivalence` with `band` in (0, 1], or `rule: difference`
// (no band); none when absent.
std::optional<DecisionRule> DecisionOf(const YAML::Node& node, const std::string& source) {
  if (!node || node.IsNull()) return std::nullopt;
  const std::string expected = "a mapping {rule: equivalence, band: 0.2} or {rule: difference}";
  Require(node.IsMap(), "experiment '{}': key 'decision' is '{}': expected {}", source,
          FlowText(node), expected);
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    Require(key == "rule" || key == "band",
            "experiment '{}': key 'decision.{}' is unknown: expected 'rule' and, for "
            "equivalence, 'band'",
            source, key);
  }
  const YAML::Node rule = node["rule"];
  const std::string name = rule && rule.IsScalar() ? rule.as<std::string>() : "";
  DecisionRule decision;
  if (name == "equivalence") {
    decision.kind = DecisionRule::Kind::kEquivalence;
  } else if (name == "difference") {
    decision.kind = DecisionRule::Kind::kDifference;
  } else {
    Fail("experiment '{}': key 'decision.rule' is {}: expected 'equivalence' or 'difference'",
         source, rule ? fmt::format("'{}'", FlowText(rule)) : std::string("missing"));
  }
  const YAML::Node band = node["band"];
  if (decision.kind == DecisionRule::Kind::kDifference) {
    Require(!band,
            "experiment '{}': key 'decision.band' is '{}': expected none with 'rule: "
            "difference' (a band belongs to 'equivalence')",
            source, FlowText(band));
    return decision;
  }
  bool valid = band && band.IsScalar();
  if (valid) {
    try {
      decision.band = band.as<double>();
    } catch (const YAML::Exception&) {
      valid = false;
    }
  }
  Require(valid && std::isfinite(decision.band) && decision.band > 0.0 && decision.band <= 1.0,
          "experiment '{}': key 'decision.band' is {}: expected a share of the first setting's "
          "mean in (0, 1], e.g. 0.2 for +-20%",
          source, band ? fmt::format("'{}'", FlowText(band)) : std::string("missing"));
  return decision;
}

}  // namespace

bool IsExperimentDir(const fs::path& dir) { return fs::is_regular_file(dir / kExperimentFile); }

std::string Sha256OfFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  Require(static_cast<bool>(in), "cannot read '{}' to hash it", path.string());
  std::stringstream bytes;
  bytes << in.rdbuf();
  const std::string text = bytes.str();
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  Require(EVP_Digest(text.data(), text.size(), digest.data(), &length, EVP_sha256(), nullptr) == 1,
          "could not hash '{}' (OpenSSL's SHA-256 failed)", path.string());
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

namespace {

// experiment.yaml as a mapping of known keys; throws cmbrl::Error naming bad YAML or an unknown
// key.
YAML::Node LoadExperimentDocument(const std::string& source) {
  YAML::Node document;
  try {
    document = YAML::LoadFile(source);
  } catch (const YAML::Exception& error) {
    Fail("experiment '{}' is not valid YAML: {}", source, error.what());
  }
  Require(document.IsMap(), "experiment '{}' must be a mapping of keys to values", source);
  const std::set<std::string> known = {"family", "configs", "tasks", "methods", "seeds",
                                       "window", "set",     "axes",  "decision"};
  for (const auto& entry : document) {
    const std::string key = entry.first.as<std::string>();
    Require(known.count(key) == 1, "experiment '{}': unknown key '{}'{}: expected one of {}",
            source, key, DidYouMean(key, known), fmt::join(known, ", "));
  }
  return document;
}

// The names listed at `key`, each one of `known` (the registries' tasks or methods).
std::vector<std::string> KnownNamesAt(const YAML::Node& document, const char* key,
                                      const std::vector<std::string>& known,
                                      const std::string& source) {
  std::vector<std::string> names = ListAt<std::string>(document, key, source);
  for (const std::string& name : names) {
    Require(std::find(known.begin(), known.end(), name) != known.end(),
            "experiment '{}': key '{}' holds '{}': expected some of {}", source, key, name,
            fmt::join(known, ", "));
  }
  return names;
}

// The agent steps counted (key `window`).
std::int64_t WindowOf(const YAML::Node& window, const std::string& source) {
  std::int64_t steps = 0;
  try {
    Require(window && window.IsScalar(), "");
    steps = window.as<std::int64_t>();
  } catch (const std::exception&) {
    Fail("experiment '{}': key 'window' is {}: expected the number of agent steps counted "
         "(3000, or the paper's 10000)",
         source, window ? fmt::format("'{}'", FlowText(window)) : std::string("missing"));
  }
  Require(steps >= 1 && steps <= kMaxTotalSteps,
          "experiment '{}': key 'window' is {}: expected 1 to {}", source, steps, kMaxTotalSteps);
  return steps;
}

// The axes of overrides (key `axes`: config keys to lists of values), none when absent.
std::vector<SweepAxis> AxesOf(const YAML::Node& axes, const std::string& source) {
  std::vector<SweepAxis> list;
  if (!axes || axes.IsNull()) return list;
  Require(axes.IsMap(), "experiment '{}': key 'axes' is '{}': expected a mapping of config "
          "keys to lists of values", source, FlowText(axes));
  for (const auto& entry : axes) {
    SweepAxis axis;
    axis.key = entry.first.as<std::string>();
    Require(entry.second.IsSequence() && entry.second.size() > 0,
            "experiment '{}': axis '{}' is '{}': expected a non-empty list of values", source,
            axis.key, FlowText(entry.second));
    for (const YAML::Node& value : entry.second) axis.values.push_back(FlowText(value));
    list.push_back(axis);
  }
  return list;
}

}  // namespace

Experiment LoadExperiment(const fs::path& dir, const fs::path& configs_dir) {
  Experiment e;
  e.dir = dir.lexically_normal();
  fs::path absolute = fs::absolute(dir).lexically_normal();
  if (absolute.filename().empty()) absolute = absolute.parent_path();  // "experiments/x/"
  e.name = absolute.filename().string();
  const std::string source = e.file().string();
  Require(IsExperimentDir(dir), "'{}' is not an experiment: expected a folder holding {}",
          dir.string(), kExperimentFile);
  const YAML::Node document = LoadExperimentDocument(source);

  // The presets: --config-dir, else the experiment's own folder (key configs, relative to
  // the experiment), else the repository's configs/.
  const YAML::Node own = document["configs"];
  Require(!own || (own.IsScalar() && !own.Scalar().empty()),
          "experiment '{}': key 'configs' is '{}': expected a folder of presets, relative to "
          "the experiment",
          source, own ? FlowText(own) : std::string());
  if (!configs_dir.empty()) {
    e.configs_dir = configs_dir;
  } else if (own) {
    e.configs_dir = (absolute / own.Scalar()).lexically_normal();
    Require(fs::is_directory(e.configs_dir), "experiment '{}': key 'configs' is '{}': no folder {}",
            source, own.Scalar(), e.configs_dir.string());
  } else {
    // experiments/<name> of a checkout: the checkout's configs/. Elsewhere (an experiment of
    // one's own in any folder): the presets of the source tree this program was built from.
    e.configs_dir = absolute.parent_path().parent_path() / "configs";
    if (!fs::is_directory(e.configs_dir)) e.configs_dir = DefaultConfigsDir();
    Require(fs::is_directory(e.configs_dir),
            "experiment '{}': its presets are looked for in the folder two above it "
            "({}) and in this program's source tree ({}); neither exists: name the presets' "
            "folder with the key 'configs' (relative to the experiment)",
            source, (absolute.parent_path().parent_path() / "configs").string(),
            DefaultConfigsDir());
  }
  Require(document["family"] && document["family"].IsScalar(),
          "experiment '{}': key 'family' is missing: expected 'paper' or the name of a preset "
          "family in {} (cpu, quickstart)", source, e.configs_dir.string());
  e.family = document["family"].as<std::string>();
  Require(e.family == "paper" || fs::is_regular_file(e.configs_dir / (e.family + ".yaml")),
          "experiment '{}': key 'family' is '{}': expected 'paper' or a family with a file "
          "{}/<family>.yaml",
          source, e.family, e.configs_dir.string());
  // Tasks of one's own (a task file's, a Python environment's) need presets of their own.
  e.tasks = own ? ListAt<std::string>(document, "tasks", source)
                : KnownNamesAt(document, "tasks", EnvNames(), source);
  e.methods = KnownNamesAt(document, "methods", MethodNames(), source);
  e.seeds = ListAt<std::uint64_t>(document, "seeds", source);
  Require(std::set<std::uint64_t>(e.seeds.begin(), e.seeds.end()).size() == e.seeds.size(),
          "experiment '{}': key 'seeds' repeats a seed in [{}]: each run needs its own", source,
          fmt::join(e.seeds, ", "));
  e.window = WindowOf(document["window"], source);
  e.overrides = OverridesOf(document["set"], "set", source);
  e.axes = AxesOf(document["axes"], source);
  e.decision = DecisionOf(document["decision"], source);
  e.sha256 = Sha256OfFile(e.file());
  if (!e.family_file().empty()) e.family_sha256 = Sha256OfFile(e.family_file());
  // Every run's config must resolve now, before any run starts.
  ResolveExperimentRuns(e);
  return e;
}

SweepGrid ExperimentGrid(const Experiment& experiment) {
  SweepGrid grid;
  grid.tasks = experiment.tasks;
  grid.planners = experiment.methods;
  grid.seeds = experiment.seeds;
  grid.config_dir = experiment.configs_dir.string();
  if (!experiment.family_file().empty()) grid.overlays = {experiment.family_file().string()};
  grid.overrides = experiment.overrides;
  grid.axes = experiment.axes;
  grid.reported_dir = RunLogsDir(experiment.report_dir()).string();
  return grid;
}

std::vector<std::pair<SweepRun, TrainConfig>> ResolveExperimentRuns(const Experiment& experiment) {
  std::vector<std::pair<SweepRun, TrainConfig>> resolved;
  for (const SweepRun& run : PlanSweep(ExperimentGrid(experiment), experiment.runs_dir())) {
    TrainConfig config = LoadTrainConfig(run.config_paths);
    if (!run.overrides.empty()) {
      config = ApplyConfigOverrides(
          config, run.overrides,
          fmt::format("experiment '{}', run {}: override", experiment.file().string(), run.name));
    }
    config.seed = run.seed;
    resolved.emplace_back(run, config);
  }
  return resolved;
}

ExperimentStamp StampOf(const Experiment& experiment) {
  ExperimentStamp stamp;
  stamp.name = experiment.name;
  stamp.dir = experiment.dir.string();
  stamp.file = kExperimentFile;
  stamp.sha256 = experiment.sha256;
  stamp.family = experiment.family;
  stamp.family_sha256 = experiment.family_sha256;
  stamp.decision = experiment.decision;
  for (const SweepRun& run : PlanSweep(ExperimentGrid(experiment), experiment.runs_dir())) {
    const std::string setting = SettingOfRunName(run.name, run.task, run.planner, run.seed);
    if (std::find(stamp.settings.begin(), stamp.settings.end(), setting) == stamp.settings.end()) {
      stamp.settings.push_back(setting);
    }
  }
  return stamp;
}

void CheckRunsAgainstExperiment(const std::vector<RunRecord>& runs, const Experiment& experiment) {
  const auto resolved = ResolveExperimentRuns(experiment);
  for (const RunRecord& run : runs) {
    const auto planned = std::find_if(resolved.begin(), resolved.end(),
                                      [&](const auto& item) { return item.first.name == run.name; });
    Require(planned != resolved.end(),
            "run '{}' (in '{}') is not a run of the experiment '{}': its experiment.yaml makes "
            "none of that name; remove it, or declare it",
            run.name, run.source.string(), experiment.file().string());
    TrainConfig expected = planned->second;
    if (!expected.python.env.empty() && expected.observation_size == 0) {
      // A declared Python environment's sizes are recorded when it is made: facts of the
      // environment, not of the protocol.
      expected.observation_size = run.config.observation_size;
      expected.action_size = run.config.action_size;
    }
    // Every key of the method, the seed and the device; not the thread counts, which name the
    // machine a run was given (the results do not depend on them).
    std::vector<ConfigDifference> differences = ConfigDifferences(run.config, expected);
    if (run.config.seed != expected.seed) {
      differences.insert(differences.begin(), {"seed", std::to_string(run.config.seed),
                                               std::to_string(expected.seed)});
    }
    if (run.config.device != expected.device) {
      differences.insert(differences.begin(), {"device", run.config.device, expected.device});
    }
    Require(differences.empty(),
            "run '{}' (in '{}') was made with another config than '{}' declares now: its "
            "config.yaml has '{}: {}' where the declaration gives {}. A protocol is fixed "
            "before its runs: make the run again, or declare a new experiment",
            run.name, run.source.string(), experiment.file().string(),
            differences.empty() ? "" : differences.front().key,
            differences.empty() ? "" : differences.front().ours,
            differences.empty() ? "" : differences.front().theirs);
  }
}


}  // namespace cmbrl

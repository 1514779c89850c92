#include "cmbrl/report/setup_diff.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

#include "cmbrl/report/table_markdown.h"

namespace cmbrl {
namespace fs = std::filesystem;

namespace {

// The paper's preset of a run's task and method: configs_dir/<task>-<method>.yaml when there is
// one, else the defaults (the paper's values) with the run's task and method.
TrainConfig PaperPreset(const TrainConfig& run, const std::string& configs_dir) {
  std::string stem = run.task + "-" + MethodOf(run);
  std::transform(stem.begin(), stem.end(), stem.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  const fs::path preset = fs::path(configs_dir) / (stem + ".yaml");
  if (!configs_dir.empty() && fs::is_regular_file(preset)) return LoadTrainConfig(preset.string());
  TrainConfig paper;
  paper.task = run.task;
  paper.variant = run.variant;
  paper.algorithm = run.algorithm;
  paper.planner = run.planner;
  return paper;
}

}  // namespace

std::vector<std::string> SetupDifferences(const std::vector<RunRecord>& runs, std::int64_t window,
                                          const std::string& configs_dir) {
  std::vector<std::string> notes;
  std::set<std::string> seen;
  const auto note = [&](const std::string& text) {
    if (seen.insert(text).second) notes.push_back(text);
  };
  // Every key of every run against the paper's preset of its task and method, generic over the
  // config's keys (ConfigDifferences): (key, ours, the paper's) -> the cells that differ so.
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<std::string>> differing;
  std::vector<std::tuple<std::string, std::string, std::string>> order;
  std::map<std::string, std::set<std::uint64_t>> seeds;
  for (const RunRecord& run : runs) {
    const TrainConfig& c = run.config;
    // Seeds as Table I counts them: a run without a finished episode is not in it.
    if (!run.episodes.empty())
      seeds[c.task + " " + MethodOf(c) + " " + SettingOf(run)].insert(c.seed);
    const TrainConfig paper = PaperPreset(c, configs_dir);
    // A cell as Table I labels it, with its setting, so that a key set in one setting of a
    // task and method (an axis, or one of several experiments reported together) names that
    // setting's cell only.
    const std::string cell =
        fmt::format("{} {}", WithSetting(c.task, SettingOf(run)), MethodLabel(MethodOf(c)));
    for (const ConfigDifference& d : ConfigDifferences(c, paper)) {
      const auto key = std::make_tuple(d.key, d.ours, d.theirs);
      auto& cells = differing[key];
      if (cells.empty()) order.push_back(key);
      if (std::find(cells.begin(), cells.end(), cell) == cells.end()) cells.push_back(cell);
    }
  }
  for (const auto& key : order) {
    const auto& [name, ours, theirs] = key;
    note(fmt::format("`{}` is {}, the paper's {} ({}).", name, ours, theirs,
                     fmt::join(differing[key], ", ")));
  }
  // The paper's Table I counts MPC agents over 10,000 agent steps and leaves the model-free
  // learners out (Section V-B: their counts are orders of magnitude larger).
  const FamiliesPresent families = FamiliesIn(runs);
  if (families.mpc)
    note(fmt::format("Table I here counts the first {} agent steps; the paper's, 10,000.", window));
  if (families.model_free)
    note(
        fmt::format("Model-free runs are counted over their first {} environment steps; the "
                    "paper's Table I leaves them out (their counts are orders of magnitude "
                    "larger).",
                    window));
  size_t fewest = SIZE_MAX, most = 0;
  for (const auto& entry : seeds) {
    fewest = std::min(fewest, entry.second.size());
    most = std::max(most, entry.second.size());
  }
  if (fewest == most && fewest != 3) {
    note(fmt::format("Seeds: {} per cell, the paper 3.", fewest));
  } else if (fewest < most) {
    note(fmt::format("Seeds: {} to {} per cell (Table I gives each cell's), the paper 3.", fewest,
                     most));
  }
  note(
      "Simulator: MuJoCo 2.2.2 through our own C++ re-creation of the tasks; the paper ran "
      "mujoco_py 2.0.2.7 with MuJoCo 2.0, so contacts and solver details differ and no "
      "trajectory is the paper's.");
  note(
      "Random numbers: our generators are not NumPy's or PyTorch's, so seed 0 here is not the "
      "paper's seed 0.");
  return notes;
}

std::vector<std::string> WhereRunsWereMade(const std::vector<RunRecord>& runs) {
  std::vector<std::pair<NumericsSetup, std::vector<std::string>>> setups;  // in order of first use
  std::vector<std::string> unrecorded, moved;
  for (const RunRecord& run : runs) {
    if (run.sessions.empty()) unrecorded.push_back(run.name);
    for (size_t i = 0; i < run.sessions.size(); ++i) {
      const RunSession& session = run.sessions[i];
      auto setup = std::find_if(setups.begin(), setups.end(),
                                [&](const auto& known) { return known.first == session.setup; });
      if (setup == setups.end()) setup = setups.insert(setups.end(), {session.setup, {}});
      std::vector<std::string>& names = setup->second;
      if (std::find(names.begin(), names.end(), run.name) == names.end()) {
        names.push_back(run.name);
      }
      if (i == 0) continue;
      const std::vector<std::string> changes =
          SetupChanges(run.sessions[i - 1].setup, session.setup);
      if (!changes.empty()) {
        moved.push_back(fmt::format("{} at step {} ({})", run.name, session.steps_done,
                                    fmt::join(changes, ", ")));
      }
    }
  }
  std::vector<std::string> notes;
  for (const auto& [setup, names] : setups) {
    notes.push_back(fmt::format("{}: {} ({}).", DescribeSetup(setup), RunCount(names.size()),
                                fmt::join(names, ", ")));
  }
  if (!moved.empty()) {
    notes.push_back(fmt::format(
        "Resumed on another setup than their previous session's, so that their rows after that "
        "step are not those of an uninterrupted run: {}.",
        fmt::join(moved, "; ")));
  }
  if (!unrecorded.empty()) {
    notes.push_back(fmt::format("Not recorded (begun before runs kept sessions.jsonl): {} ({}).",
                                RunCount(unrecorded.size()), fmt::join(unrecorded, ", ")));
  }
  return notes;
}

}  // namespace cmbrl

// An experiment declared as data: experiments/<name>/experiment.yaml names the preset family,
// the tasks, the methods, the seeds, the counting window and the axes of overrides, so that a
// protocol is written once, before its runs, and `cmbrl sweep` and `cmbrl report` remake it
// from that one file. (It reads its own YAML beside config.cc, the reader of run configs: an
// experiment file is a sweep's declaration, not a run's configuration.)
//
//   family: cpu                  # configs/cpu.yaml over each configs/<task>-<method>.yaml
//   configs: presets             # optional: the presets' folder, relative to the experiment;
//                                # then tasks of one's own too (a task file's, a Python env's)
//   tasks: [PointGoal1, PointGoal2]
//   methods: [rce, cem, random]  # planners and model-free algorithms alike
//   seeds: [0, 1, 2, 3, 4]
//   window: 3000                 # agent steps counted (Table I: 10000)
//   set: {training.total_steps: 3000}           # every run (optional)
//   axes: {classifier.threshold: [0.3, 0.5]}    # one run per combination (optional)
//   decision: {rule: equivalence, band: 0.2}    # how the report decides (optional; below)
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/report/document.h"
#include "cmbrl/report/run_logs.h"
#include "cmbrl/sweep/sweep.h"

namespace cmbrl {

inline constexpr const char* kExperimentFile = "experiment.yaml";

struct Experiment {
  std::string name;            // the folder's name
  std::filesystem::path dir;   // experiments/<name>
  std::string family;          // "paper" (the presets as they are) or configs/<family>.yaml
  // Where the presets are: --config-dir, the experiment's key configs, or the repository's.
  std::filesystem::path configs_dir;
  std::vector<std::string> tasks;
  std::vector<std::string> methods;
  std::vector<std::uint64_t> seeds;
  std::int64_t window = 0;             // agent steps counted (environment steps: model-free)
  std::vector<std::string> overrides;  // "section.key=value", every run
  std::vector<SweepAxis> axes;
  // The rule that decides the study from its "Settings compared" pairs, declared before the
  // runs: `rule: equivalence` with `band` (a share of the first setting's mean, in (0, 1]), or
  // `rule: difference` (DecisionRule).
  std::optional<DecisionRule> decision;
  std::string sha256;  // of experiment.yaml's bytes, as `sha256sum` prints it
  std::string family_sha256;  // of configs/<family>.yaml ("" for the paper family)

  std::filesystem::path file() const { return dir / kExperimentFile; }
  // configs/<family>.yaml, composed over every preset (empty for the paper family).
  std::filesystem::path family_file() const {
    return family == "paper" ? std::filesystem::path() : configs_dir / (family + ".yaml");
  }
  std::filesystem::path runs_dir() const { return dir / "runs"; }      // not committed
  std::filesystem::path report_dir() const { return dir / "report"; }  // committed, with logs
};

// Whether `dir` holds an experiment.yaml.
bool IsExperimentDir(const std::filesystem::path& dir);

// Reads dir/experiment.yaml. Every task, method, seed, key and value is checked here: an unknown
// key, task or method, a family without its file, a repeated seed, an axis key that --set does
// not know or a value it refuses throws cmbrl::Error naming the file, the key and the value.
// `configs_dir` is where the presets live (the repository's configs/ when empty: two folders
// above the experiment's).
Experiment LoadExperiment(const std::filesystem::path& dir,
                          const std::filesystem::path& configs_dir = {});

// The sweep that makes the experiment's runs: its grid, into Experiment::runs_dir().
SweepGrid ExperimentGrid(const Experiment& experiment);

// Every run of the experiment with its config resolved as `cmbrl train` will resolve it (the
// presets composed, the overrides and the seed applied), in the sweep's order. Throws
// cmbrl::Error naming the run and the key for an override that does not apply.
std::vector<std::pair<SweepRun, TrainConfig>> ResolveExperimentRuns(const Experiment& experiment);

// Refuses runs that are not the experiment's: each must be named as the sweep names it and hold
// the config the declaration resolves to now. Throws cmbrl::Error naming the first run that is
// not, and the first line of its config that differs.
void CheckRunsAgainstExperiment(const std::vector<RunRecord>& runs, const Experiment& experiment);

// What a report records of the experiment (report/document.h).
ExperimentStamp StampOf(const Experiment& experiment);

// The SHA-256 of a file's bytes in hexadecimal. Throws cmbrl::Error when it cannot be read.
std::string Sha256OfFile(const std::filesystem::path& path);

}  // namespace cmbrl

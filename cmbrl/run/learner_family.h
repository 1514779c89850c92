// What the rest of cmbrl knows of a learner family, as plain data: one sheet per family (the
// MPC learner of Algorithm 2, the model-free policy optimisers). Configuration, reports and
// sweeps look a family's facts up here instead of asking which family a run is: its progress
// columns, how a report reads its log, what a run is grouped by, which config sections its
// learner reads and how much memory a run will take. Free of LibTorch, MuJoCo and XGBoost; the
// learners themselves are built by learners/registry.h. A new family is a sheet here (a file
// pair's worth: its .cc and its function below) and one entry in learners/registry.cc.
#pragma once

#include <string>
#include <vector>

#include "cmbrl/models/model_options.h"
#include "cmbrl/planning/planning_options.h"
#include "cmbrl/policy_opt/policy_opt_options.h"
#include "cmbrl/run/run_options.h"

namespace cmbrl {

// What a row of a family's progress.csv is, and so which reader a report uses.
enum class ProgressLog {
  kEpisodes,  // a row per episode: EpRet, EpCost, Steps, ... (report/ ReadProgressEpisodes)
  kEpochs,    // a row per epoch of environment steps: AverageEpRet, CumulativeCost, ...
};

// What a run of the family is grouped by in sweeps and reports (its "method").
enum class MethodAxis {
  kPlanner,    // its planner: "rce", "cem", "random"
  kAlgorithm,  // its algorithm: "trpo-lagrangian", "cpo"
};

// Bytes a run will hold in memory, part by part (an estimate from its settings). An MPC run has
// the first five parts, a model-free run the last two.
struct RunMemory {
  double transitions = 0.0;
  double labeled_states = 0.0;
  double ensemble = 0.0;
  double planning = 0.0;
  double classifier_fit = 0.0;
  double policy_networks = 0.0;  // policy and the two value functions, with gradients and Adam
  double epoch_batch = 0.0;      // an epoch's rows and the activations of a pass over them
  double total() const;
  std::string Describe() const;  // each part of the run with its config keys and GiB
};

// The settings a memory estimate reads: each component's options, borrowed from a run's config.
struct RunSizes {
  int state_dim = 0;
  int action_dim = 0;
  const TrainingLoopOptions& training;
  const EnsembleOptions& ensemble;
  const XgbCostModelOptions& classifier;
  const PlannerSettings& planning;
  const PolicyOptimisationOptions& policy_optimisation;
};

struct FamilySheet {
  std::string name;  // "MPC", "policy optimisation": for messages
  ProgressLog log;
  // The header of its progress.csv, in order (the learner's rows are checked against it).
  std::vector<std::string> progress_columns;
  MethodAxis method_axis;
  // The config sections beyond the top-level keys and `training` whose settings its learner
  // reads ("planning", "objective", ...), in the config file's order.
  std::vector<std::string> sections;
  RunMemory (*estimate_memory)(const RunSizes& sizes);

  // Whether its learner reads the config section `section`.
  bool Reads(const std::string& section) const;
  // progress_columns joined by commas: the first line of its progress.csv.
  std::string ProgressHeader() const;
};

// The sheets, one per family (run/mpc_family.cc, run/policy_opt_family.cc).
const FamilySheet& MpcFamily();
const FamilySheet& PolicyOptFamily();

}  // namespace cmbrl

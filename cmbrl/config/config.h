// Training configuration: the only place that reads YAML. Keys map one to one onto the options
// structs of the components, whose defaults are the paper's values; a file only names what it
// changes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/config/python_source.h"
#include "cmbrl/env/mujoco_task_options.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/env/variant.h"
#include "cmbrl/models/model_options.h"
#include "cmbrl/planning/planning_options.h"
#include "cmbrl/policy_opt/policy_opt_options.h"
#include "cmbrl/run/algorithms.h"
#include "cmbrl/run/learner_family.h"
#include "cmbrl/run/run_options.h"

namespace cmbrl {

struct TrainConfig {
  // A built-in task (env/task_list.h); "python:<what made it>" for an environment given from
  // Python (cmbrl.train(env=...)), e.g. "python:mypackage.envs.make_arm(links=2)"; or the name
  // of a task declared in mujoco_task.
  std::string task = "PointGoal1";
  MujocoTaskOptions mujoco_task;  // a task declared as data (mujoco_task.model set)
  // A Python environment and functions declared by name (section python): the task is then
  // "python:" + DeclaredEnvName(python.env), set where the config is read.
  PythonSourceOptions python;
  // environment.observation_size, environment.action_size: a Python environment's sizes, written
  // by cmbrl.train(env=...) so that the run is known without Python; 0 for a built-in task.
  int observation_size = 0;
  int action_size = 0;
  Variant variant = Variant::kPaper;  // parsed once, where the file is read
  Spawn spawn = Spawn::kStanding;     // environment.spawn
  // environment.previous_action: the action the environment last ran appended to every
  // observation (env/previous_action_env.h), for robots whose motion depends on it.
  bool previous_action = false;
  std::string algorithm = "mpc";      // AlgorithmNames() (run/algorithms.h)
  std::string planner = "rce";        // rce, cem or random (algorithm mpc)
  std::uint64_t seed = 0;
  std::string device = "cpu";  // models and planner
  TrainingLoopOptions training;
  EnsembleOptions ensemble;
  XgbCostModelOptions classifier;
  PlannerSettings planning;
  TrajectoryObjectiveOptions objective;
  StepModelOptions reward_model;       // objective.reward: learned
  StepModelOptions termination_model;  // objective.termination: learned
  PolicyOptimisationOptions policy_optimisation;  // the model-free algorithms
};

// Whether the run's environment is a Python one: given from Python (task "python:...") or
// declared by name (python.env), whatever its task is called.
inline bool IsPythonEnvTask(const TrainConfig& config) {
  return IsPythonTask(config.task) || !config.python.env.empty();
}

// What a run's results are grouped by in sweeps and reports (run/algorithms.h): the planner of
// an MPC run ("rce"), the algorithm of a model-free one ("cpo").
inline std::string MethodOf(const TrainConfig& config) {
  return MethodOf(config.algorithm, config.planner);
}

// The analytic reward form an MPC run plans with (objective.reward: analytic): a declared
// task's mujoco_task.reward; else objective.analytic_form, or the task's own (env/task_list.h)
// where that is "".
std::string AnalyticRewardForm(const TrainConfig& config);

// Bytes a run will hold in memory, part by part: its family's estimate (run/learner_family.h)
// from the config's options.
RunMemory EstimateRunMemory(const TrainConfig& config, int state_dim, int action_dim);

// Reads a YAML file. Throws cmbrl::Error naming the file, the key (as section.key) and the value
// for a missing file, invalid YAML, an unknown key, a value of the wrong type or a bad setting.
TrainConfig LoadTrainConfig(const std::string& path);

// Several YAML files composed in order: each names only the keys it changes, later files over
// earlier ones (a mapping merges into a mapping), e.g. a task's paper preset and then a preset
// family (configs/cpu.yaml). Throws as LoadTrainConfig does, naming the files.
TrainConfig LoadTrainConfig(const std::vector<std::string>& paths);

// Whether any of the files (as LoadTrainConfig composes them) names the top-level key `key`,
// e.g. "task": a run whose files name no task would silently be the defaults' full paper-size
// PointGoal1 run. Throws as LoadTrainConfig does for a file it cannot read.
bool ConfigFilesNameKey(const std::vector<std::string>& paths, const std::string& key);

// The same from YAML text; `source` names it in messages.
TrainConfig ParseTrainConfig(const std::string& yaml, const std::string& source);

// Checks every setting (task, variant, planner, device and each component's options, for example
// more elites than samples or a horizon of 0, each within a bound), and that what the run will
// allocate fits this machine; throws cmbrl::Error naming the key.
void ValidateTrainConfig(const TrainConfig& config, const std::string& source);

// Sets the one device of the models and the planner ("cpu", "cuda", "cuda:N").
void SetTrainDevice(TrainConfig& config, const std::string& device);

// Every key with its value, in the layout LoadTrainConfig reads.
std::string TrainConfigToYaml(const TrainConfig& config);

// A key whose value differs between two configs, as the config file writes them.
struct ConfigDifference {
  std::string key;     // "planning.population", or "task" for a top-level key
  std::string ours;    // the first config's value, as YAML ("100", "[256, 256, 256]")
  std::string theirs;  // the second's
};

// Every key of the config (the one table of keys every reader and writer visits) whose value
// differs between `ours` and `theirs`, in the table's order. The seed, the device and the
// thread counts, which name a run or the machine rather than its method, are left out.
std::vector<ConfigDifference> ConfigDifferences(const TrainConfig& ours, const TrainConfig& theirs);

// `config` with each "section.key=value" (or "key=value" for a top-level key) of `overrides`
// applied in order, the value read as YAML ("500", "0.3", "[256, 256]"), then validated as a
// file would be. Throws cmbrl::Error naming `source` (where the overrides came from, e.g.
// "--set") and the override for a malformed one, an unknown key or a bad value.
TrainConfig ApplyConfigOverrides(const TrainConfig& config,
                                 const std::vector<std::string>& overrides,
                                 const std::string& source);

}  // namespace cmbrl

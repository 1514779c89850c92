// The training algorithms a run can have (its config's `algorithm`), listed once with their
// paper's names and the family of learner that trains them, and the methods runs are grouped by.
// Free of LibTorch, MuJoCo and XGBoost, so that reports and sweeps can name and group runs
// without linking the learners; the factories are in learners/registry.h. Adding an algorithm of
// an existing family is one line in algorithms.cc.
#pragma once

#include <string>
#include <vector>

#include "cmbrl/run/learner_family.h"

namespace cmbrl {

// How a model-free algorithm keeps the cost under its limit.
enum class ConstraintRule { kNone, kLagrangian, kCpo };

struct AlgorithmEntry {
  std::string name;           // the config's `algorithm`: "mpc", "trpo-lagrangian", ...
  std::string label;          // the paper's name: "MPC", "TRPO-Lagrangian", ...
  const FamilySheet* family;  // what trains it, and so what a row of its progress.csv is
  ConstraintRule constraint = ConstraintRule::kNone;  // policy optimisation only
  bool first_order = false;  // PPO's clipped steps instead of a trust region (model-free only)
};

// Every algorithm, "mpc" first, then the paper's model-free baselines and PPO's variants.
const std::vector<AlgorithmEntry>& Algorithms();

// Every algorithm's name, in Algorithms()'s order.
std::vector<std::string> AlgorithmNames();

// The entry of `name`, or nullptr when none has it.
const AlgorithmEntry* FindAlgorithmOrNull(const std::string& name);

// The entry of `name`; throws cmbrl::Error naming it and the known ones otherwise.
const AlgorithmEntry& FindAlgorithm(const std::string& name);

// The sheet of the family that trains `algorithm` (throws for an unknown one).
const FamilySheet& FamilyOf(const std::string& algorithm);

// What a run is grouped by in sweeps and reports (its family's MethodAxis): the planner of an
// MPC run ("rce"), the algorithm of a model-free one ("cpo").
std::string MethodOf(const std::string& algorithm, const std::string& planner);

// Every method in the paper's order: the planners, then the model-free algorithms.
std::vector<std::string> MethodNames();

// The paper's name of a method ("MPC-RCE", "TRPO-Lagrangian"), or the name itself when unknown.
std::string MethodLabel(const std::string& method);

}  // namespace cmbrl

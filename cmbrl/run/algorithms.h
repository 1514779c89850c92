// The training algorithms a run can have (its config's `algorithm`), listed once with their
// paper's names and what kind of learner trains them. Free of LibTorch, MuJoCo and XGBoost, so
// that reports and sweeps can name and group runs without linking the learners; the factories
// are in learners/registry.h. Adding an algorithm is one line here and one in the registry.
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

// Which learner trains an algorithm, and so what a row of its progress.csv is.
enum class LearnerFamily {
  kMpc,                 // the paper's Algorithm 2: a row per MPC episode
  kPolicyOptimisation,  // the model-free baselines: a row per epoch of environment steps
};

// How a model-free algorithm keeps the cost under its limit.
enum class ConstraintRule { kNone, kLagrangian, kCpo };

struct AlgorithmEntry {
  std::string name;   // the config's `algorithm`: "mpc", "trpo-lagrangian", ...
  std::string label;  // the paper's name: "MPC", "TRPO-Lagrangian", ...
  LearnerFamily family;
  ConstraintRule constraint = ConstraintRule::kNone;  // policy optimisation only
  bool first_order = false;  // PPO's clipped steps instead of a trust region (model-free only)
};

// Every algorithm, "mpc" first, then the paper's model-free baselines and PPO's variants.
const std::vector<AlgorithmEntry>& Algorithms();

// The entry of `name`, or nullptr when none has it.
const AlgorithmEntry* FindAlgorithmOrNull(const std::string& name);

// The entry of `name`; throws cmbrl::Error naming it and the known ones otherwise.
const AlgorithmEntry& FindAlgorithm(const std::string& name);

// Whether the algorithm is trained by the MPC learner (throws for an unknown one).
inline bool IsMpcAlgorithm(const std::string& name) {
  return FindAlgorithm(name).family == LearnerFamily::kMpc;
}

}  // namespace cmbrl

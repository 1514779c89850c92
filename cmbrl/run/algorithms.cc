#include "cmbrl/run/algorithms.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "cmbrl/core/check.h"

namespace cmbrl {

const std::vector<AlgorithmEntry>& Algorithms() {
  static const std::vector<AlgorithmEntry> entries = {
      {"mpc", "MPC", LearnerFamily::kMpc},
      {"trpo", "TRPO", LearnerFamily::kPolicyOptimisation, ConstraintRule::kNone},
      {"trpo-lagrangian", "TRPO-Lagrangian", LearnerFamily::kPolicyOptimisation,
       ConstraintRule::kLagrangian},
      {"cpo", "CPO", LearnerFamily::kPolicyOptimisation, ConstraintRule::kCpo},
      {"ppo", "PPO", LearnerFamily::kPolicyOptimisation, ConstraintRule::kNone, true},
      {"ppo-lagrangian", "PPO-Lagrangian", LearnerFamily::kPolicyOptimisation,
       ConstraintRule::kLagrangian, true},
  };
  return entries;
}

const AlgorithmEntry* FindAlgorithmOrNull(const std::string& name) {
  const auto& entries = Algorithms();
  const auto it = std::find_if(entries.begin(), entries.end(),
                               [&](const AlgorithmEntry& e) { return e.name == name; });
  return it == entries.end() ? nullptr : &*it;
}

const AlgorithmEntry& FindAlgorithm(const std::string& name) {
  if (const AlgorithmEntry* entry = FindAlgorithmOrNull(name)) return *entry;
  std::vector<std::string> names;
  for (const AlgorithmEntry& entry : Algorithms()) names.push_back(entry.name);
  Fail("unknown algorithm '{}': expected one of {}", name, fmt::join(names, ", "));
}

}  // namespace cmbrl

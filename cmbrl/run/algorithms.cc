#include "cmbrl/run/algorithms.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"

namespace cmbrl {

const std::vector<AlgorithmEntry>& Algorithms() {
  static const std::vector<AlgorithmEntry> entries = {
      {"mpc", "MPC", &MpcFamily()},
      {"trpo", "TRPO", &PolicyOptFamily(), ConstraintRule::kNone},
      {"trpo-lagrangian", "TRPO-Lagrangian", &PolicyOptFamily(), ConstraintRule::kLagrangian},
      {"cpo", "CPO", &PolicyOptFamily(), ConstraintRule::kCpo},
      {"ppo", "PPO", &PolicyOptFamily(), ConstraintRule::kNone, true},
      {"ppo-lagrangian", "PPO-Lagrangian", &PolicyOptFamily(), ConstraintRule::kLagrangian, true},
  };
  return entries;
}

std::vector<std::string> AlgorithmNames() {
  std::vector<std::string> names;
  for (const AlgorithmEntry& entry : Algorithms()) names.push_back(entry.name);
  return names;
}

const AlgorithmEntry* FindAlgorithmOrNull(const std::string& name) {
  const auto& entries = Algorithms();
  const auto it = std::find_if(entries.begin(), entries.end(),
                               [&](const AlgorithmEntry& e) { return e.name == name; });
  return it == entries.end() ? nullptr : &*it;
}

const AlgorithmEntry& FindAlgorithm(const std::string& name) {
  if (const AlgorithmEntry* entry = FindAlgorithmOrNull(name)) return *entry;
  Fail("unknown algorithm '{}'{}: expected one of {}", name, DidYouMean(name, AlgorithmNames()),
       fmt::join(AlgorithmNames(), ", "));
}

const FamilySheet& FamilyOf(const std::string& algorithm) {
  return *FindAlgorithm(algorithm).family;
}

std::string MethodOf(const std::string& algorithm, const std::string& planner) {
  return FamilyOf(algorithm).method_axis == MethodAxis::kPlanner ? planner : algorithm;
}

std::vector<std::string> MethodNames() {
  std::vector<std::string> names;
  bool planners_listed = false;  // the planners stand once, where the first family of them is
  for (const AlgorithmEntry& entry : Algorithms()) {
    if (entry.family->method_axis == MethodAxis::kAlgorithm) {
      names.push_back(entry.name);
    } else if (!planners_listed) {
      const std::vector<std::string> planners = PlannerNames();
      names.insert(names.end(), planners.begin(), planners.end());
      planners_listed = true;
    }
  }
  return names;
}

std::string MethodLabel(const std::string& method) {
  const AlgorithmEntry* algorithm = FindAlgorithmOrNull(method);
  return algorithm != nullptr && algorithm->family->method_axis == MethodAxis::kAlgorithm
             ? algorithm->label
             : PlannerLabel(method);
}

}  // namespace cmbrl

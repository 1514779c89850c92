#include "cmbrl/planning/planner_registry.h"

#include <fmt/ranges.h>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

std::unique_ptr<Planner> MakeCrossEntropy(const PlannerSettings& settings, EliteRule rule,
                                          std::uint64_t seed) {
  CrossEntropyOptions options = settings.cross_entropy;
  options.penalty = settings.penalty;
  return std::make_unique<CrossEntropyPlanner>(settings.problem, options, rule, seed);
}

PlanWork CrossEntropyWork(const PlannerSettings& s) {
  return {s.cross_entropy.population, s.cross_entropy.max_iterations};
}

}  // namespace

const std::vector<PlannerEntry>& Planners() {
  static const std::vector<PlannerEntry> entries = {
      {"rce", "MPC-RCE", Propagation::kPerMember, /*is_papers_method=*/true,
       [](const PlannerSettings& s, std::uint64_t seed) {
         return MakeCrossEntropy(s, EliteRule::kRobust, seed);
       },
       CrossEntropyWork},
      {"cem", "MPC-CEM", Propagation::kEnsembleMean, false,
       [](const PlannerSettings& s, std::uint64_t seed) {
         return MakeCrossEntropy(s, EliteRule::kPenalty, seed);
       },
       CrossEntropyWork},
      {"random", "MPC-random", Propagation::kEnsembleMean, false,
       [](const PlannerSettings& s, std::uint64_t seed) -> std::unique_ptr<Planner> {
         RandomShootingOptions options = s.random;
         options.penalty = s.penalty;
         return std::make_unique<RandomShootingPlanner>(s.problem, options, seed);
       },
       [](const PlannerSettings& s) { return PlanWork{s.random.samples, 1}; }},
  };
  return entries;
}

std::vector<std::string> PlannerNames() {
  std::vector<std::string> names;
  for (const PlannerEntry& entry : Planners()) names.push_back(entry.name);
  return names;
}

const PlannerEntry* FindPlannerOrNull(const std::string& name) {
  for (const PlannerEntry& entry : Planners()) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

const PlannerEntry& FindPlanner(const std::string& name) {
  if (const PlannerEntry* entry = FindPlannerOrNull(name)) return *entry;
  Fail("unknown planner '{}': expected one of {}", name, fmt::join(PlannerNames(), ", "));
}

std::string PlannerLabel(const std::string& name) {
  const PlannerEntry* entry = FindPlannerOrNull(name);
  return entry != nullptr ? entry->label : name;
}

std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed) {
  return FindPlanner(name).make(settings, seed);
}

}  // namespace cmbrl

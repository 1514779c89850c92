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
      {FindPlannerInfo("rce"),
       [](const PlannerSettings& s, std::uint64_t seed) {
         return MakeCrossEntropy(s, EliteRule::kRobust, seed);
       },
       CrossEntropyWork},
      {FindPlannerInfo("cem"),
       [](const PlannerSettings& s, std::uint64_t seed) {
         return MakeCrossEntropy(s, EliteRule::kPenalty, seed);
       },
       CrossEntropyWork},
      {FindPlannerInfo("random"),
       [](const PlannerSettings& s, std::uint64_t seed) -> std::unique_ptr<Planner> {
         RandomShootingOptions options = s.random;
         options.penalty = s.penalty;
         return std::make_unique<RandomShootingPlanner>(s.problem, options, seed);
       },
       [](const PlannerSettings& s) { return PlanWork{s.random.samples, 1}; }},
  };
  return entries;
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

std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed) {
  return FindPlanner(name).make(settings, seed);
}

}  // namespace cmbrl

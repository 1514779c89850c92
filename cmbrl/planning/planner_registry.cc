#include "cmbrl/planning/planner_registry.h"

#include <fmt/ranges.h>

#include "cmbrl/core/check.h"

namespace cmbrl {

const std::vector<std::string>& PlannerNames() {
  static const std::vector<std::string> names = {"rce", "cem", "random"};
  return names;
}

std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed) {
  if (name == "rce") {
    return std::make_unique<CrossEntropyPlanner>(settings.problem, settings.cross_entropy,
                                                 EliteRule::kRobust, seed);
  }
  if (name == "cem") {
    return std::make_unique<CrossEntropyPlanner>(settings.problem, settings.cross_entropy,
                                                 EliteRule::kPenalty, seed);
  }
  if (name == "random") {
    return std::make_unique<RandomShootingPlanner>(settings.problem, settings.random, seed);
  }
  Fail("unknown planner '{}': expected one of {}", name, fmt::join(PlannerNames(), ", "));
}

}  // namespace cmbrl

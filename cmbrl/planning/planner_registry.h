// The planners by name: one line each in planner_registry.cc.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/planning/cross_entropy.h"
#include "cmbrl/planning/random_shooting.h"

namespace cmbrl {

// Settings of every planner; each planner reads its own part.
struct PlannerSettings {
  PlanningProblem problem;
  CrossEntropyOptions cross_entropy;  // "cem", "rce"
  RandomShootingOptions random;       // "random"
};

// "rce", "cem", "random".
const std::vector<std::string>& PlannerNames();

// Throws cmbrl::Error naming an unknown planner and the known ones, or a bad setting.
std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed);

}  // namespace cmbrl

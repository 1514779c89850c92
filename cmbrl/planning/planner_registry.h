// The planners built: one entry for each of PlannerInfos() (planning_options.cc, the one list of
// planners), made by its search's factory in planner_registry.cc. An entry carries everything the
// rest of the program asks about a planner, so nothing outside planning/ compares its name.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/planning/cross_entropy.h"
#include "cmbrl/planning/random_shooting.h"
#include "cmbrl/planning/sample_economy.h"
#include "cmbrl/planning/trajectory_objective.h"

namespace cmbrl {

// The model evaluations one plan costs at most: the action sequences scored at each iteration.
struct PlanWork {
  std::vector<std::int64_t> samples;  // one value per iteration

  int iterations() const { return static_cast<int>(samples.size()); }
  std::int64_t total() const;    // sequences scored in one plan
  std::int64_t largest() const;  // the largest iteration's
};

struct PlannerEntry : PlannerInfo {
  std::function<std::unique_ptr<Planner>(const PlannerSettings&, std::uint64_t seed)> make;
  std::function<PlanWork(const PlannerSettings&)> work;  // for benchmarks' FLOP counts
};

// Every planner, in PlannerInfos()'s order.
const std::vector<PlannerEntry>& Planners();

// The entry of a planner; throws cmbrl::Error naming an unknown planner and the known ones.
const PlannerEntry& FindPlanner(const std::string& name);

// The entry of a planner, or nullptr for a name this build does not know.
const PlannerEntry* FindPlannerOrNull(const std::string& name);

// Throws cmbrl::Error naming an unknown planner and the known ones, or a bad setting.
std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed);

}  // namespace cmbrl

// The planners by name: one entry each in planner_registry.cc. An entry carries everything the
// rest of the program asks about a planner, so nothing outside planning/ compares its name.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/planning/cross_entropy.h"
#include "cmbrl/planning/random_shooting.h"
#include "cmbrl/planning/trajectory_objective.h"

namespace cmbrl {

// Settings of every planner; each planner reads its own part.
struct PlannerSettings {
  PlanningProblem problem;
  CrossEntropyOptions cross_entropy;  // "cem", "rce"
  RandomShootingOptions random;       // "random"
  // CEM and random: a sample's score is reward_cost + penalty * constraint_cost (facts B2). One
  // value for both, which their factories hand to the planner's own options.
  double penalty = 500.0;
};

// The model evaluations one plan costs at most: `samples` action sequences scored per iteration.
struct PlanWork {
  std::int64_t samples = 0;
  int iterations = 0;
};

struct PlannerEntry {
  std::string name;         // "rce": configs and the command line
  std::string label;        // "MPC-RCE": the paper's name, for reports
  Propagation propagation;  // how its samples go through the ensemble (facts B2)
  // The paper's method, whose claim ("violates least at comparable reward") reports check
  // against every other planner.
  bool is_papers_method = false;
  std::function<std::unique_ptr<Planner>(const PlannerSettings&, std::uint64_t seed)> make;
  std::function<PlanWork(const PlannerSettings&)> work;  // for benchmarks' FLOP counts
};

// Every planner, the paper's order: rce, cem, random.
const std::vector<PlannerEntry>& Planners();

// "rce", "cem", "random".
std::vector<std::string> PlannerNames();

// The entry of a planner; throws cmbrl::Error naming an unknown planner and the known ones.
const PlannerEntry& FindPlanner(const std::string& name);

// The entry of a planner, or nullptr for a name this build does not know.
const PlannerEntry* FindPlannerOrNull(const std::string& name);

// The entry's label, or the name itself for a planner this build does not know (reports of
// sweeps made by other builds).
std::string PlannerLabel(const std::string& name);

// Throws cmbrl::Error naming an unknown planner and the known ones, or a bad setting.
std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed);

}  // namespace cmbrl

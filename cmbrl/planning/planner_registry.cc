#include "cmbrl/planning/planner_registry.h"

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
  // One entry per PlannerInfos() entry, in its order: FindPlanner relies on it.
  static const bool aligned = [] {
    bool same = entries.size() == PlannerInfos().size();
    for (size_t i = 0; same && i < entries.size(); ++i) {
      same = entries[i].name == PlannerInfos()[i].name;
    }
    return same;
  }();
  Require(aligned, "the planner registry does not follow PlannerInfos() one for one");
  return entries;
}

namespace {

// The entries follow PlannerInfos() one for one (Planners() checks it), so a planner's entry is
// found through its info: one lookup, one error message.
const PlannerEntry& EntryOf(const PlannerInfo& info) {
  return Planners()[static_cast<size_t>(&info - PlannerInfos().data())];
}

}  // namespace

const PlannerEntry* FindPlannerOrNull(const std::string& name) {
  const PlannerInfo* info = FindPlannerInfoOrNull(name);
  return info != nullptr ? &EntryOf(*info) : nullptr;
}

const PlannerEntry& FindPlanner(const std::string& name) {
  return EntryOf(FindPlannerInfo(name));
}

std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed) {
  return FindPlanner(name).make(settings, seed);
}

}  // namespace cmbrl

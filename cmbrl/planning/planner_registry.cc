#include "cmbrl/planning/planner_registry.h"

#include <algorithm>
#include <numeric>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

PlanWork CrossEntropyWork(const PlannerSettings& s) {
  // Every iteration is computed, converged ones masked (cross_entropy.h).
  return {std::vector<std::int64_t>(static_cast<size_t>(s.cross_entropy.max_iterations),
                                    s.cross_entropy.population)};
}

PlanWork SampleEconomyWork(const PlannerSettings& s) {
  // The new samples, the kept elites beside them (at the first iteration too, once a plan has
  // been made), and the mean among the last iteration's.
  PlanWork work;
  const int kept = KeptElites(s.cross_entropy, s.economy);
  for (const std::int64_t drawn : EconomyPopulations(s.cross_entropy, s.economy)) {
    work.samples.push_back(drawn + kept);
  }
  work.samples.back() += 1;
  return work;
}

// The factory of a planner's search: the one place that turns a PlannerInfo into code.
PlannerEntry EntryOf(const PlannerInfo& info) {
  const auto cross_entropy = [&info](EliteRule rule) {
    return PlannerEntry{info,
                        [rule](const PlannerSettings& s, std::uint64_t seed) {
                          return std::make_unique<CrossEntropyPlanner>(
                              s.problem, s.cross_entropy, rule, s.penalty, seed);
                        },
                        CrossEntropyWork};
  };
  switch (info.search) {
    case PlannerSearch::kRobustCrossEntropy:
      return cross_entropy(EliteRule::kRobust);
    case PlannerSearch::kPenaltyCrossEntropy:
      return cross_entropy(EliteRule::kPenalty);
    case PlannerSearch::kRandomShooting:
      return {info,
              [](const PlannerSettings& s, std::uint64_t seed) -> std::unique_ptr<Planner> {
                return std::make_unique<RandomShootingPlanner>(s.problem, s.random, s.penalty,
                                                               seed);
              },
              [](const PlannerSettings& s) { return PlanWork{{s.random.samples}}; }};
    case PlannerSearch::kRobustSampleEconomy:
      return {info,
              [](const PlannerSettings& s, std::uint64_t seed) -> std::unique_ptr<Planner> {
                return std::make_unique<SampleEconomyPlanner>(s.problem, s.cross_entropy,
                                                              s.economy, EliteRule::kRobust,
                                                              s.penalty, seed);
              },
              SampleEconomyWork};
  }
  Fail("planner '{}' has a search the registry cannot build", info.name);
}

}  // namespace

std::int64_t PlanWork::total() const {
  return std::accumulate(samples.begin(), samples.end(), std::int64_t{0});
}

std::int64_t PlanWork::largest() const {
  return samples.empty() ? 0 : *std::max_element(samples.begin(), samples.end());
}

const std::vector<PlannerEntry>& Planners() {
  // Derived from PlannerInfos(), one for one and in its order: FindPlanner relies on it.
  static const std::vector<PlannerEntry> entries = [] {
    std::vector<PlannerEntry> built;
    for (const PlannerInfo& info : PlannerInfos()) built.push_back(EntryOf(info));
    return built;
  }();
  return entries;
}

const PlannerEntry* FindPlannerOrNull(const std::string& name) {
  const PlannerInfo* info = FindPlannerInfoOrNull(name);
  return info != nullptr ? &Planners()[static_cast<size_t>(info - PlannerInfos().data())]
                         : nullptr;
}

const PlannerEntry& FindPlanner(const std::string& name) {
  const PlannerInfo& info = FindPlannerInfo(name);
  return Planners()[static_cast<size_t>(&info - PlannerInfos().data())];
}

std::unique_ptr<Planner> MakePlanner(const std::string& name, const PlannerSettings& settings,
                                     std::uint64_t seed) {
  return FindPlanner(name).make(settings, seed);
}

}  // namespace cmbrl

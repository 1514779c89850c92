#include "cmbrl/planning/planning_options.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"

namespace cmbrl {

void ValidatePlanningProblem(const PlanningProblem& p) {
  Require(p.horizon >= 1 && p.horizon <= 1000, "horizon is {}: expected 1 to 1000 steps",
          p.horizon);
  Require(p.action_dim >= 1, "action_dim is {}: expected at least 1", p.action_dim);
  Require(
      std::abs(p.action_low) <= 1e6 && std::abs(p.action_high) <= 1e6 &&
          p.action_low < p.action_high,
      "action_low and action_high are {} and {}: expected numbers from -1e6 to 1e6 with "
      "action_low < action_high (the planner samples in float32)",
      p.action_low, p.action_high);
}

void ValidateCrossEntropyOptions(const CrossEntropyOptions& o) {
  Require(o.population >= 1 && o.population <= 1'000'000,
          "population is {}: expected 1 to 1000000", o.population);
  Require(o.elites >= 1 && o.elites <= o.population,
          "elites is {}: expected between 1 and population ({})", o.elites, o.population);
  Require(o.min_feasible_elites >= 1 && o.min_feasible_elites <= o.elites,
          "min_feasible_elites is {}: expected between 1 and elites ({})", o.min_feasible_elites,
          o.elites);
  Require(o.max_iterations >= 1 && o.max_iterations <= 1000,
          "max_iterations is {}: expected 1 to 1000", o.max_iterations);
  // Actions lie in [-1, 1]: their variance is at most 1, so an epsilon above it ends every
  // search after one iteration (a choice), and far above, a typing slip.
  Require(o.epsilon >= 0 && o.epsilon <= 1000, "epsilon is {}: expected a number in [0, 1000]",
          o.epsilon);
  Require(o.alpha >= 0 && o.alpha < 1, "alpha is {}: expected a number in [0, 1)", o.alpha);
  Require(o.initial_variance > 0 && o.initial_variance <= 100,
          "initial_variance is {}: expected a number in (0, 100]", o.initial_variance);
}

void ValidateSampleEconomyOptions(const SampleEconomyOptions& o) {
  Require(o.population_decay >= 1 && o.population_decay <= 100,
          "population_decay is {}: expected a number in [1, 100] (1: every iteration draws the "
          "whole population; iCEM: 1.25)",
          o.population_decay);
  Require(o.keep_elites >= 0 && o.keep_elites <= 1,
          "keep_elites is {}: expected a share of the elites in [0, 1] (iCEM: 0.3)",
          o.keep_elites);
  ValidateNoiseExponent(o.noise_exponent);
}

void ValidateNoiseExponent(double noise_exponent) {
  Require(noise_exponent >= 0 && noise_exponent <= 10,
          "noise_exponent is {}: expected a number in [0, 10] (0: white noise; iCEM: 2 to 4)",
          noise_exponent);
}

std::vector<std::int64_t> EconomyPopulations(const CrossEntropyOptions& search,
                                             const SampleEconomyOptions& economy) {
  // Never fewer than twice the elites (iCEM's floor), nor more than the first population.
  const std::int64_t floor = std::min<std::int64_t>(2 * search.elites, search.population);
  std::vector<std::int64_t> populations;
  for (int i = 0; i < search.max_iterations; ++i) {
    const double drawn = std::round(search.population / std::pow(economy.population_decay, i));
    populations.push_back(std::max(floor, static_cast<std::int64_t>(drawn)));
  }
  return populations;
}

int KeptElites(const CrossEntropyOptions& search, const SampleEconomyOptions& economy) {
  // The small margin keeps 0.3 * 10 at 3 although 0.3 is not exact in binary.
  return static_cast<int>(std::floor(economy.keep_elites * search.elites + 1e-9));
}

void ValidateRandomShootingOptions(const RandomShootingOptions& o) {
  Require(o.samples >= 1 && o.samples <= 10'000'000,
          "random_samples is {}: expected 1 to 10000000", o.samples);
}

void ValidatePenalty(double penalty) {
  Require(penalty >= 0 && penalty <= 1e9, "penalty is {}: expected a number in [0, 1e9]",
          penalty);
}

std::vector<std::string> RewardSourceNames() { return {"analytic", "learned", "python"}; }

std::vector<std::string> AnalyticRewardNames() {
  return {kGoalDistanceReward, kGoalLidarDistanceReward, kPushLidarDistancesReward,
          kCircleLidarSpeedReward};
}

std::vector<std::string> TerminationSourceNames() { return {"learned", "none", "python"}; }

void RequireGoalIndexFits(const TrajectoryObjectiveOptions& o, int state_dim) {
  Require(o.goal_index >= 0 && o.goal_index + 1 < state_dim,
          "goal_index is {}: expected 0 to {} for a state of {} dimensions", o.goal_index,
          state_dim - 2, state_dim);
}

void ValidateTrajectoryObjectiveOptions(const TrajectoryObjectiveOptions& o, int state_dim) {
  const std::vector<std::string> sources = RewardSourceNames();
  Require(std::find(sources.begin(), sources.end(), o.reward) != sources.end(),
          "reward is '{}'{}: expected one of {} (analytic: the task's own form of the "
          "predicted states; learned: a model fitted on the run's rewards; python: a function "
          "given from Python)",
          o.reward, DidYouMean(o.reward, sources), fmt::join(sources, ", "));
  const std::vector<std::string> terminations = TerminationSourceNames();
  Require(std::find(terminations.begin(), terminations.end(), o.termination) !=
              terminations.end(),
          "termination is '{}'{}: expected one of {} (learned: a model fitted on the steps "
          "that ended the run's episodes; none: the task has no terminal state; python: a "
          "function given from Python)",
          o.termination, DidYouMean(o.termination, terminations), fmt::join(terminations, ", "));
  // Only the analytic goal distance reads the goal's place in the state (state_dim 0: a state
  // whose size is not known yet, a declared task's, which plans with its own form).
  Require(o.goal_index >= 0 && o.goal_index < 1'000'000,
          "goal_index is {}: expected an index into the state, 0 or more", o.goal_index);
  if (o.reward == "analytic" && state_dim != 0) RequireGoalIndexFits(o, state_dim);
  Require(o.gamma > 0 && o.gamma <= 1, "gamma is {}: expected a number in (0, 1]", o.gamma);
  Require(o.beta > 0 && o.beta <= 1, "beta is {}: expected a number in (0, 1]", o.beta);
  Require(o.near_goal_radius >= 0 && o.near_goal_radius <= 100 && o.at_goal_radius >= 0 &&
              o.at_goal_radius <= 100,
          "near_goal_radius is {} and at_goal_radius {}: expected metres from 0 to 100",
          o.near_goal_radius, o.at_goal_radius);
  Require(std::isfinite(o.near_goal_bonus) && std::abs(o.near_goal_bonus) <= 1e6 &&
              std::isfinite(o.at_goal_bonus) && std::abs(o.at_goal_bonus) <= 1e6,
          "near_goal_bonus is {} and at_goal_bonus {}: expected numbers from -1e6 to 1e6",
          o.near_goal_bonus, o.at_goal_bonus);
}

const std::vector<PlannerInfo>& PlannerInfos() {
  static const std::vector<PlannerInfo> infos = {
      {"rce", "MPC-RCE", PlannerSearch::kRobustCrossEntropy, Propagation::kPerMember,
       /*is_papers_method=*/true},
      {"cem", "MPC-CEM", PlannerSearch::kPenaltyCrossEntropy, Propagation::kEnsembleMean, false},
      {"random", "MPC-random", PlannerSearch::kRandomShooting, Propagation::kEnsembleMean, false},
      {"rce-icem", "MPC-RCE-iCEM", PlannerSearch::kRobustSampleEconomy, Propagation::kPerMember,
       false, /*in_paper=*/false},
  };
  return infos;
}

std::vector<std::string> PlannerNames() {
  std::vector<std::string> names;
  for (const PlannerInfo& info : PlannerInfos()) names.push_back(info.name);
  return names;
}

std::vector<std::string> PaperPlannerNames() {
  std::vector<std::string> names;
  for (const PlannerInfo& info : PlannerInfos()) {
    if (info.in_paper) names.push_back(info.name);
  }
  return names;
}

const PlannerInfo* FindPlannerInfoOrNull(const std::string& name) {
  for (const PlannerInfo& info : PlannerInfos()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

const PlannerInfo& FindPlannerInfo(const std::string& name) {
  if (const PlannerInfo* info = FindPlannerInfoOrNull(name)) return *info;
  Fail("unknown planner '{}'{}: expected one of {}", name, DidYouMean(name, PlannerNames()),
       fmt::join(PlannerNames(), ", "));
}

std::string PlannerLabel(const std::string& name) {
  const PlannerInfo* info = FindPlannerInfoOrNull(name);
  return info != nullptr ? info->label : name;
}

}  // namespace cmbrl

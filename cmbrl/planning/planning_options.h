// What a planner is asked to do, as plain data: the planners' names and labels, their options and
// the objective's, and the checks of each. Free of LibTorch, so that configuration, sweeps and
// reports can read and check settings without linking the planners; the planners themselves are
// in planner_registry.h, one for each of PlannerInfos(): adding a planner of a known search is one
// line in PlannerInfos().
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cmbrl {

// Box bounds and sizes shared by every planner.
struct PlanningProblem {
  int horizon = 8;     // H
  int action_dim = 2;  // A
  double action_low = -1.0;
  double action_high = 1.0;
  std::string device = "cpu";
};

// Throws cmbrl::Error naming a bad horizon, action size or bounds.
void ValidatePlanningProblem(const PlanningProblem& problem);

struct CrossEntropyOptions {
  int population = 500;         // samples per iteration
  int elites = 12;              // samples that update the distribution
  int min_feasible_elites = 5;  // RCE: with fewer feasible samples, pad with least violating
  int max_iterations = 8;
  double epsilon = 0.01;          // stop once the largest variance is at most this
  double alpha = 0.1;             // new = alpha * old + (1 - alpha) * elite statistic
  double initial_variance = 1.0;  // the mean starts at 0
  bool warm_start = false;        // start from the previous plan shifted one step (paper: off)
};

// Throws cmbrl::Error naming the first bad field (more elites than samples, ...).
void ValidateCrossEntropyOptions(const CrossEntropyOptions& options);

// iCEM's sample economy (Pinneri et al. 2020) inside a cross-entropy search: the "rce-icem"
// planner (sample_economy.h). It reads population (the first iteration's), elites,
// min_feasible_elites, max_iterations (each one run: no early stop, so epsilon is not read),
// alpha and initial_variance from CrossEntropyOptions, and these.
struct SampleEconomyOptions {
  // Iteration i draws max(population / population_decay^i, 2 elites) new samples (iCEM's 1.25).
  double population_decay = 1.25;
  // The share of the elites (rounded down) carried into the next iteration, and shifted by one
  // step into the next plan's first (iCEM's 0.3).
  double keep_elites = 0.3;
  // Colored noise: power proportional to 1 / f^noise_exponent along the horizon (0: white).
  double noise_exponent = 2.0;
};

// Throws cmbrl::Error naming the first bad field.
void ValidateSampleEconomyOptions(const SampleEconomyOptions& options);

// Throws cmbrl::Error naming a noise_exponent outside [0, 10] (colored_noise.h).
void ValidateNoiseExponent(double noise_exponent);

// New samples drawn at each iteration (max_iterations values), by population_decay.
std::vector<std::int64_t> EconomyPopulations(const CrossEntropyOptions& search,
                                          const SampleEconomyOptions& economy);

// How many elites are kept from one iteration to the next: floor(keep_elites * elites).
int KeptElites(const CrossEntropyOptions& search, const SampleEconomyOptions& economy);

struct RandomShootingOptions {
  int samples = 5000;  // uniform action sequences
};

// Throws cmbrl::Error naming the first bad field.
void ValidateRandomShootingOptions(const RandomShootingOptions& options);

// Where the objective's reward term comes from (objective.reward): "analytic", the task's own
// form of its predicted states (env/task_list.h names it; planning/reward_term.h builds it), or
// "python", a vectorised Python function that the program training the run gives
// (cmbrl.train(..., reward=f)).
std::vector<std::string> RewardSourceNames();

// The analytic reward forms: "goal-distance" (the paper's Goal tasks', facts B2, on the ego-state
// vector), and three on a stock task's lidar observation (planning/reward_term.h):
// "goal-lidar-distance" (Button; stock Goal), "push-lidar-distances" (Push) and
// "circle-lidar-speed" (Circle).
inline constexpr const char* kGoalDistanceReward = "goal-distance";
inline constexpr const char* kGoalLidarDistanceReward = "goal-lidar-distance";
inline constexpr const char* kPushLidarDistancesReward = "push-lidar-distances";
inline constexpr const char* kCircleLidarSpeedReward = "circle-lidar-speed";
std::vector<std::string> AnalyticRewardNames();

// Where the objective's termination signal comes from (objective.termination): "none" (the
// task has none: the Goal tasks' episodes end by time alone, which the horizon never reaches),
// "learned", a model fitted on the steps that ended the run's episodes by themselves, or
// "python", a vectorised Python function (cmbrl.train(..., termination=f)).
std::vector<std::string> TerminationSourceNames();

struct TrajectoryObjectiveOptions {
  std::string reward = "analytic";  // RewardSourceNames()
  std::string termination = "none";  // TerminationSourceNames()
  // The analytic reward's form (AnalyticRewardNames()); "" for the task's own. A run on an
  // environment given from Python names one to plan with an analytic reward.
  std::string analytic_form;
  // The goal-distance form's parameters.
  int goal_index = 6;             // state[goal_index], state[goal_index + 1]: goal in ego XY
  double gamma = 0.98;            // discount of the reward cost (and of CEM's constraint cost)
  double beta = 0.4;              // RCE: discount of the constraint count
  double near_goal_radius = 0.2;  // m: a predicted state this close earns near_goal_bonus
  double near_goal_bonus = 5.0;
  double at_goal_radius = 0.1;  // m: and this close a further at_goal_bonus
  double at_goal_bonus = 8.0;
  // The original's code tests at_goal_radius on the distance already lowered by
  // near_goal_bonus, so every d < near_goal_radius earns both bonuses (facts B2: d - 13 below
  // 0.2, which is what produced Table I). false: the written rule, at_goal_bonus only below
  // at_goal_radius.
  bool at_goal_test_after_near_bonus = true;
};

// Throws cmbrl::Error unless the goal-distance form's goal (state[goal_index], the next value)
// lies in a state of `state_dim` values.
void RequireGoalIndexFits(const TrajectoryObjectiveOptions& options, int state_dim);

// Throws cmbrl::Error naming the first bad field.
void ValidateTrajectoryObjectiveOptions(const TrajectoryObjectiveOptions& options, int state_dim);

enum class Propagation {
  // CEM and random: one trajectory from the ensemble-mean prediction; reward cost
  // sum_t gamma^t d_t, constraint cost sum_t gamma^t unsafe_t (the planner adds the penalty).
  kEnsembleMean,
  // RCE: every member rolls its own trajectory (TS-infinity); reward cost is the members' mean of
  // sum_t gamma^t d_t, constraint cost the members' max of sum_t beta^t unsafe_t.
  kPerMember,
};

// Settings of every planner; each planner reads its own part.
struct PlannerSettings {
  PlanningProblem problem;
  CrossEntropyOptions cross_entropy;  // "cem", "rce", and "rce-icem" with economy
  SampleEconomyOptions economy;       // "rce-icem"
  RandomShootingOptions random;       // "random"
  // CEM and random: a sample's score is reward_cost + penalty * constraint_cost (facts B2). One
  // value for both, handed to the planner by its factory (planner_registry.cc).
  double penalty = 500.0;
};

// Throws cmbrl::Error naming a penalty that is negative or not finite.
void ValidatePenalty(double penalty);

// The search a planner runs, which planner_registry.cc builds: a new kind of search is a case
// there, a new planner of a known kind a line in PlannerInfos() alone.
enum class PlannerSearch {
  kRobustCrossEntropy,   // RCE: cross-entropy, elites chosen among the feasible (Algorithm 1)
  kPenaltyCrossEntropy,  // CEM: cross-entropy, elites by reward_cost + penalty * constraint_cost
  kRandomShooting,       // the best of uniform action sequences by the same penalised score
  // RCE's elite rule inside iCEM's sample economy: colored noise, elites kept across
  // iterations and plans, a shrinking population; acts on its best sample (sample_economy.h)
  kRobustSampleEconomy,
};

// What the rest of the program may know of a planner without building one.
struct PlannerInfo {
  std::string name;         // "rce": configs and the command line
  std::string label;        // "MPC-RCE": the paper's name, for reports
  PlannerSearch search;     // what it runs
  Propagation propagation;  // how its samples go through the ensemble (facts B2)
  // The paper's method, whose claim ("violates least at comparable reward") reports check
  // against every other planner.
  bool is_papers_method = false;
  // One of the paper's planners (its Table I's MPC rows): what a sweep runs unless told.
  bool in_paper = true;
};

// Every planner: the paper's, in its order (rce, cem, random), then rce-icem.
const std::vector<PlannerInfo>& PlannerInfos();

// "rce", "cem", "random", "rce-icem".
std::vector<std::string> PlannerNames();

// The paper's planners: "rce", "cem", "random".
std::vector<std::string> PaperPlannerNames();

// The planner called `name`, or nullptr for a name this build does not know.
const PlannerInfo* FindPlannerInfoOrNull(const std::string& name);

// The planner called `name`; throws cmbrl::Error naming it and the known ones otherwise.
const PlannerInfo& FindPlannerInfo(const std::string& name);

// The planner's label, or the name itself for a planner this build does not know (reports of
// sweeps made by other builds).
std::string PlannerLabel(const std::string& name);

}  // namespace cmbrl

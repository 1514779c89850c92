// Model predictive control with learned models (paper Algorithm 2, inner loop): plan from the
// current observation, execute the first action, plan again at the next step.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/agent/policy.h"
#include "cmbrl/models/cost_model.h"
#include "cmbrl/models/dynamics_model.h"
#include "cmbrl/planning/planner_registry.h"
#include "cmbrl/planning/trajectory_objective.h"

namespace cmbrl {

// Host copies of one plan's figures.
struct PlanStats {
  double milliseconds = 0.0;  // wall time of the plan, the action's copy to the host included
  int iterations = 0;
  double feasible_fraction = 0.0;  // of the last population
  double infeasible_elite_fraction = 0.0;
};

// The MPC agent: RCE plans on per-member rollouts, CEM and random on the ensemble mean (facts
// B2). Borrows the models, which must outlive it. One host synchronisation per action. Not
// thread-safe.
class MpcAgent final : public Policy {
 public:
  // `planner`: "rce", "cem" or "random"; `reward` and `termination`: the objective's terms
  // (RewardTermFor and TerminationTermFor in mpc_parts.h; no termination by default). Throws
  // cmbrl::Error for bad settings.
  MpcAgent(const DynamicsModel& dynamics, const CostModel& cost, const std::string& planner,
           const PlannerSettings& settings, const TrajectoryObjectiveOptions& objective,
           std::unique_ptr<RewardTerm> reward, std::uint64_t seed,
           std::unique_ptr<TerminationTerm> termination = nullptr);

  void BeginEpisode() override { planner_->Reset(); }

  // Throws cmbrl::Error when the observation has the wrong size or a non-finite value, or when
  // the models predicted NaN or infinity for any sample of the plan.
  std::vector<double> Act(const std::vector<double>& observation) override;

  // The objective's scores of action sequences (N, H, A) within the action bounds, from
  // `observation`, with the agent's own models: plans of several planners judged alike (a
  // frozen-model comparison). The last plan's figures and result stay; the objective's last
  // trajectories become these. Throws cmbrl::Error as Act does for the observation, and for
  // sequences of another shape or outside the bounds.
  ObjectiveValues Score(const std::vector<double>& observation, const torch::Tensor& sequences);

  int horizon() const { return horizon_; }
  const PlanStats& last_plan() const { return last_plan_; }
  const PlanResult& last_result() const { return last_result_; }
  Planner& planner() { return *planner_; }
  TrajectoryObjective& objective() { return objective_; }

 private:
  // Checks the observation and sets it as the objective's start state.
  void SetObservation(const std::vector<double>& observation);

  const DynamicsModel& dynamics_;
  torch::Device device_;
  int horizon_;
  double low_, high_;  // the action bounds
  std::unique_ptr<Planner> planner_;
  TrajectoryObjective objective_;
  PlanStats last_plan_;
  PlanResult last_result_;
};

}  // namespace cmbrl

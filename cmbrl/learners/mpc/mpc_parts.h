// The parts of an MPC run built from its configuration, in one place: the environment (through
// the registry), the dynamics ensemble, the constraint classifier and the MPC agent. Training,
// evaluation and the benchmarks assemble them here.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "cmbrl/learners/learner_inputs.h"
#include "cmbrl/learners/mpc/mpc_agent.h"
#include "cmbrl/env/env.h"
#include "cmbrl/config/config.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/step_model.h"
#include "cmbrl/models/xgboost_cost_model.h"

namespace cmbrl {

// Models and agent borrow nothing from each other beyond what MpcAgent documents: the agent
// borrows the models, so they live here together. Not thread-safe.
struct MpcParts {
  std::unique_ptr<Env> env;
  std::unique_ptr<EnsembleDynamics> ensemble;
  // What the agent plans with: the ensemble, or the ensemble with the previous action echoed
  // into its predictions where the observation holds it (environment.previous_action).
  std::unique_ptr<DynamicsModel> planning_dynamics;

  // The model the agent plans with: planning_dynamics where there is one, else the ensemble.
  const DynamicsModel& planner_dynamics() const {
    return planning_dynamics ? *planning_dynamics : *ensemble;
  }
  std::unique_ptr<XgbCostModel> classifier;
  std::unique_ptr<StepModel> reward_model;       // objective.reward: learned only
  std::unique_ptr<StepModel> termination_model;  // objective.termination: learned only
  std::unique_ptr<MpcAgent> agent;
};

// The seeds of the parts. Training derives them from the run seed (DeriveSeed with the
// SeedStream of each); evaluation and benchmarks choose their own.
struct MpcPartSeeds {
  std::uint64_t ensemble = 0;
  std::uint64_t classifier = 0;
  std::uint64_t planner = 0;
  std::uint64_t reward_model = 0;
  std::uint64_t termination_model = 0;
};

// The run's own streams of `seed`.
MpcPartSeeds RunSeeds(std::uint64_t seed);

// Builds everything for `config` (a validated configuration), the objective's terms by
// RewardTermFor and TerminationTermFor.
// Throws cmbrl::Error for settings the components refuse.
MpcParts AssembleMpc(const TrainConfig& config, const MpcPartSeeds& seeds,
                     const LearnerInputs& inputs = {});

// The planning objective's reward term of `config` (objective.reward): for "analytic", its
// task's own form (env/task_list.h) or objective.analytic_form, with the objective's options;
// for "python", the one `inputs` makes; for "learned", `learned`'s predictions (which the term
// borrows); a declared task's own form reads its sensor's components by their names in
// `observation`. Throws cmbrl::Error naming the key when the run needs a Python function and
// none is given.
std::unique_ptr<RewardTerm> RewardTermFor(const TrainConfig& config,
                                          const LearnerInputs& inputs = {},
                                          const StepModel* learned = nullptr,
                                          const BoxSpec* observation = nullptr);

// Its termination term (objective.termination): none (nullptr), the one `inputs` makes, or
// for "learned" `learned`'s probabilities (which the term borrows). Throws as RewardTermFor does.
std::unique_ptr<TerminationTerm> TerminationTermFor(const TrainConfig& config,
                                                    const LearnerInputs& inputs = {},
                                                    const StepModel* learned = nullptr);

// The planner settings of `config` for an environment with `action_dim` actions.
PlannerSettings PlannerSettingsFor(const TrainConfig& config, int action_dim);

}  // namespace cmbrl

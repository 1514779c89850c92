// A trained run's agent, loaded from its last checkpoint to act outside training: the MPC agent
// with its dynamics ensemble and constraint classifier, or a model-free run's policy (its mean
// action). Evaluation and the Python module act through it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/agent/policy.h"
#include "cmbrl/env/env.h"
#include "cmbrl/config/config.h"
#include "cmbrl/learners/registry.h"
#include "cmbrl/models/dynamics_model.h"

namespace cmbrl {

class MpcAgent;
class EnsembleDynamics;
class XgbCostModel;

// Not thread-safe.
class LoadedRun {
 public:
  // Loads run_dir's config and verified checkpoint; `seed` seeds the environment it builds and
  // the MPC planner. `overrides` ("section.key=value", ApplyConfigOverrides) change how the
  // trained models are used, never the models: only keys of PlanningOverrideKeys() are
  // accepted. Throws cmbrl::Error when run_dir holds no trained run or for a bad override.
  // `inputs`: what the agent needs beside the run's config (a Python reward function).
  LoadedRun(const std::string& run_dir, std::uint64_t seed,
            const std::vector<std::string>& overrides = {}, const LearnerInputs& inputs = {});

  // What an override may name: "planning.*", "objective.*", "classifier.threshold",
  // "classifier.predict_threads" and "planner" (the planner, its settings and objective, and how
  // the classifier's probability becomes a verdict; an MPC run's models serve every planner).
  static const std::vector<std::string>& PlanningOverrideKeys();
  ~LoadedRun();

  const TrainConfig& config() const { return config_; }
  bool is_mpc() const { return agent_.mpc != nullptr; }
  // The environment built with the agent (an MPC run's models are shaped by it).
  Env& env();

  // Acts as in training's evaluation: BeginEpisode at each episode's start, then Act per step.
  Policy& policy();

  // The MPC run's parts; each throws cmbrl::Error for a model-free run.
  MpcAgent& mpc_agent();
  const EnsembleDynamics& dynamics() const;
  // What the planner predicts with: dynamics(), with the planned action written into the
  // previous action's components where the run observes it (environment.previous_action).
  const DynamicsModel& planning_dynamics() const;
  const XgbCostModel& classifier() const;

 private:
  TrainConfig config_;
  TrainedAgent agent_;  // its family's registration loaded it
};

}  // namespace cmbrl

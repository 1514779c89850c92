#include "cmbrl/eval/loaded_run.h"

#include <fmt/ranges.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/learners/mpc/mpc_learner.h"
#include "cmbrl/learners/mpc/mpc_parts.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"
#include "cmbrl/run/run_directory.h"

namespace cmbrl {

struct LoadedRun::Mpc {
  MpcParts parts;
};

// A model-free run: its policy alone, and an environment to act in.
struct LoadedRun::ModelFree {
  std::unique_ptr<Env> env;
  std::unique_ptr<GaussianMeanPolicy> policy;
};

namespace {

// Whether `item` ("section.key=value") names a key that PlanningOverrideKeys allows.
bool IsPlanningOverride(const std::string& item) {
  const std::string key = item.substr(0, item.find('='));
  for (const std::string& allowed : LoadedRun::PlanningOverrideKeys()) {
    const bool whole_section =
        allowed.size() > 2 && allowed.compare(allowed.size() - 2, 2, ".*") == 0;
    if (whole_section ? key.rfind(allowed.substr(0, allowed.size() - 1), 0) == 0 : key == allowed) {
      return true;
    }
  }
  return false;
}

}  // namespace

const std::vector<std::string>& LoadedRun::PlanningOverrideKeys() {
  static const std::vector<std::string> keys = {"planning.*", "objective.*", "classifier.threshold",
                                                "classifier.predict_threads", "planner"};
  return keys;
}

LoadedRun::LoadedRun(const std::string& run_dir, std::uint64_t seed,
                     const std::vector<std::string>& overrides) {
  const RunDirectory run(run_dir);
  Require(run.HoldsRun(), "'{}' holds no run (no {})", run_dir,
          run.config_file().filename().string());
  // Refuses a checkpoint whose files were changed.
  Require(VerifiedCheckpoint(run).has_value(), "'{}' holds no trained run yet (no checkpoint)",
          run_dir);
  config_ = LoadTrainConfig(run.config_file().string());
  for (const std::string& item : overrides) {
    Require(IsPlanningOverride(item),
            "override '{}': only {} can change for a trained run (the others shape its models)",
            item, fmt::join(PlanningOverrideKeys(), ", "));
  }
  if (!overrides.empty()) config_ = ApplyConfigOverrides(config_, overrides, "overrides");
  if (IsMpcAlgorithm(config_.algorithm)) {
    mpc_ = std::make_unique<Mpc>();
    mpc_->parts =
        AssembleMpc(config_, MpcPartSeeds{seed, seed, DeriveSeed(seed, kPlannerSeedStream)});
    LoadMpcModels(run.checkpoint_dir(), mpc_->parts);
  } else {
    model_free_ = std::make_unique<ModelFree>();
    model_free_->env = MakeEnv(config_.task, config_.variant, config_.spawn);
    model_free_->policy = LoadPolicyOptMeanPolicy(config_, run.checkpoint_dir(),
                                                  model_free_->env->observation_spec().size(),
                                                  model_free_->env->action_spec());
  }
}

LoadedRun::~LoadedRun() = default;

Env& LoadedRun::env() { return mpc_ ? *mpc_->parts.env : *model_free_->env; }

Policy& LoadedRun::policy() {
  if (mpc_) return *mpc_->parts.agent;
  return *model_free_->policy;
}

MpcAgent& LoadedRun::mpc_agent() {
  Require(mpc_ != nullptr, "the run is '{}', not an MPC run: it has no planner", config_.algorithm);
  return *mpc_->parts.agent;
}

const EnsembleDynamics& LoadedRun::dynamics() const {
  Require(mpc_ != nullptr, "the run is '{}', not an MPC run: it has no dynamics model",
          config_.algorithm);
  return *mpc_->parts.ensemble;
}

const XgbCostModel& LoadedRun::classifier() const {
  Require(mpc_ != nullptr, "the run is '{}', not an MPC run: it has no constraint classifier",
          config_.algorithm);
  return *mpc_->parts.classifier;
}

}  // namespace cmbrl

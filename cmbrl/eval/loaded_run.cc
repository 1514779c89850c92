#include "cmbrl/eval/loaded_run.h"

#include <fmt/ranges.h>

#include "cmbrl/core/check.h"
#include "cmbrl/learners/mpc/mpc_parts.h"
#include "cmbrl/run/run_directory.h"

namespace cmbrl {

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
                     const std::vector<std::string>& overrides, const LearnerInputs& inputs) {
  const RunDirectory run(run_dir);
  Require(run.HoldsRun(), "'{}' holds no run (no {})", run_dir,
          run.config_file().filename().string());
  // Refuses a checkpoint whose files were changed.
  Require(VerifiedCheckpoint(run).has_value(), "'{}' holds no trained run yet (no checkpoint)",
          run_dir);
  config_ = LoadTrainConfig(run.config_file().string());
  const FamilySheet& family = FamilyOf(config_.algorithm);
  for (const std::string& item : overrides) {
    Require(IsPlanningOverride(item),
            "override '{}': only {} can change for a trained run (the others shape its models)",
            item, fmt::join(PlanningOverrideKeys(), ", "));
    // Each applies to a planner: a family that plans with none would ignore it.
    const std::string key = item.substr(0, item.find('='));
    const size_t dot = key.find('.');
    const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
    Require(section.empty() ? family.Reads("planning") : family.Reads(section),
            "override '{}': a {} run ({}) has no planner, objective or classifier to change: "
            "evaluate it without overrides",
            item, family.name, config_.algorithm);
  }
  if (!overrides.empty()) config_ = ApplyConfigOverrides(config_, overrides, "overrides");
  agent_ = RegistrationOf(FamilyOf(config_.algorithm))
               .load_agent(config_, LastCheckpointDir(run), seed,
                           WithDeclaredPython(config_, inputs));
}

LoadedRun::~LoadedRun() = default;

Env& LoadedRun::env() { return *agent_.env; }

Policy& LoadedRun::policy() { return *agent_.policy; }

MpcAgent& LoadedRun::mpc_agent() {
  Require(agent_.mpc != nullptr, "the run is '{}', not an MPC run: it has no planner",
          config_.algorithm);
  return *agent_.mpc->agent;
}

const EnsembleDynamics& LoadedRun::dynamics() const {
  Require(agent_.mpc != nullptr, "the run is '{}', not an MPC run: it has no dynamics model",
          config_.algorithm);
  return *agent_.mpc->ensemble;
}

const DynamicsModel& LoadedRun::planning_dynamics() const {
  dynamics();  // refuses a model-free run
  return agent_.mpc->planner_dynamics();
}

const XgbCostModel& LoadedRun::classifier() const {
  Require(agent_.mpc != nullptr,
          "the run is '{}', not an MPC run: it has no constraint classifier",
          config_.algorithm);
  return *agent_.mpc->classifier;
}

}  // namespace cmbrl

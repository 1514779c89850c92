#include "cmbrl/learners/mpc/mpc_parts.h"

#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"

namespace cmbrl {

MpcPartSeeds RunSeeds(std::uint64_t seed) {
  return {DeriveSeed(seed, kEnsembleSeedStream), DeriveSeed(seed, kClassifierSeedStream),
          DeriveSeed(seed, kPlannerSeedStream)};
}

std::unique_ptr<RewardTerm> RewardTermFor(const TrainConfig& config,
                                          const LearnerInputs& inputs) {
  if (config.objective.reward == "python") {
    Require(static_cast<bool>(inputs.python_reward),
            "objective.reward is 'python': the run plans with a reward function given from "
            "Python (cmbrl.train(..., reward=f), cmbrl.load_run(..., reward=f)); the command "
            "line has none");
    return inputs.python_reward();
  }
  // "analytic": the task's own form (validated with the config).
  return MakeAnalyticReward(AnalyticRewardForm(config), config.objective);
}

std::unique_ptr<TerminationTerm> TerminationTermFor(const TrainConfig& config,
                                                    const LearnerInputs& inputs) {
  if (config.objective.termination == "none") return nullptr;
  // "python" (validated with the config).
  Require(static_cast<bool>(inputs.python_termination),
          "objective.termination is 'python': the run plans with a termination function given "
          "from Python (cmbrl.train(..., termination=f), cmbrl.load_run(..., termination=f)); "
          "the command line has none");
  return inputs.python_termination();
}

PlannerSettings PlannerSettingsFor(const TrainConfig& config, int action_dim) {
  PlannerSettings settings = config.planning;
  settings.problem.action_dim = action_dim;
  return settings;
}

MpcParts AssembleMpc(const TrainConfig& config, const MpcPartSeeds& seeds,
                     const LearnerInputs& inputs) {
  MpcParts parts;
  parts.env = MakeRunEnv(config, inputs);
  const int state_dim = parts.env->observation_spec().size();
  const int action_dim = parts.env->action_spec().size();
  parts.ensemble =
      std::make_unique<EnsembleDynamics>(state_dim, action_dim, config.ensemble, seeds.ensemble);
  parts.classifier =
      std::make_unique<XgbCostModel>(state_dim, config.classifier, seeds.classifier);
  parts.agent = std::make_unique<MpcAgent>(*parts.ensemble, *parts.classifier, config.planner,
                                           PlannerSettingsFor(config, action_dim),
                                           config.objective, RewardTermFor(config, inputs),
                                           seeds.planner, TerminationTermFor(config, inputs));
  return parts;
}

}  // namespace cmbrl

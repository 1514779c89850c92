#include "cmbrl/learners/mpc/mpc_parts.h"

#include "cmbrl/core/rng.h"
#include "cmbrl/env/registry.h"

namespace cmbrl {

MpcPartSeeds RunSeeds(std::uint64_t seed) {
  return {DeriveSeed(seed, kEnsembleSeedStream), DeriveSeed(seed, kClassifierSeedStream),
          DeriveSeed(seed, kPlannerSeedStream)};
}

std::unique_ptr<RewardTerm> RewardTermFor(const TrainConfig& config) {
  // objective.reward is "analytic", the one source RewardSourceNames() offers (validated).
  return MakeAnalyticReward(FindTask(config.task).analytic_reward, config.objective);
}

PlannerSettings PlannerSettingsFor(const TrainConfig& config, int action_dim) {
  PlannerSettings settings = config.planning;
  settings.problem.action_dim = action_dim;
  return settings;
}

MpcParts AssembleMpc(const TrainConfig& config, const MpcPartSeeds& seeds) {
  MpcParts parts;
  parts.env = MakeEnv(config.task, config.variant, config.spawn);
  const int state_dim = parts.env->observation_spec().size();
  const int action_dim = parts.env->action_spec().size();
  parts.ensemble =
      std::make_unique<EnsembleDynamics>(state_dim, action_dim, config.ensemble, seeds.ensemble);
  parts.classifier =
      std::make_unique<XgbCostModel>(state_dim, config.classifier, seeds.classifier);
  parts.agent = std::make_unique<MpcAgent>(*parts.ensemble, *parts.classifier, config.planner,
                                           PlannerSettingsFor(config, action_dim),
                                           config.objective, RewardTermFor(config),
                                           seeds.planner);
  return parts;
}

}  // namespace cmbrl

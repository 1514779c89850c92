#include "cmbrl/learners/registry.h"

#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/rng.h"
#include "cmbrl/learners/mpc/mpc_agent.h"
#include "cmbrl/learners/mpc/mpc_learner.h"
#include "cmbrl/learners/mpc/mpc_parts.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"
#include "cmbrl/models/ensemble.h"
#include "cmbrl/models/xgboost_cost_model.h"

namespace cmbrl {

TrainedAgent::TrainedAgent() = default;
TrainedAgent::~TrainedAgent() = default;
TrainedAgent::TrainedAgent(TrainedAgent&&) noexcept = default;
TrainedAgent& TrainedAgent::operator=(TrainedAgent&&) noexcept = default;

namespace {

TrainedAgent LoadMpcAgent(const TrainConfig& config, const std::filesystem::path& checkpoint,
                          std::uint64_t seed, const LearnerInputs& inputs) {
  TrainedAgent loaded;
  loaded.mpc = std::make_unique<MpcParts>(
      AssembleMpc(config, MpcPartSeeds{seed, seed, DeriveSeed(seed, kPlannerSeedStream), seed, seed},
                  inputs));
  LoadMpcModels(checkpoint, *loaded.mpc);
  loaded.env = loaded.mpc->env.get();
  loaded.policy = loaded.mpc->agent.get();
  return loaded;
}

TrainedAgent LoadPolicyOptAgent(const TrainConfig& config,
                                const std::filesystem::path& checkpoint, std::uint64_t,
                                const LearnerInputs& inputs) {
  TrainedAgent loaded;
  loaded.owned_env = MakeRunEnv(config, inputs);
  loaded.owned_policy = LoadPolicyOptMeanPolicy(config, checkpoint,
                                                loaded.owned_env->observation_spec().size(),
                                                loaded.owned_env->action_spec());
  loaded.env = loaded.owned_env.get();
  loaded.policy = loaded.owned_policy.get();
  return loaded;
}

const std::vector<LearnerRegistration>& Registrations() {
  static const std::vector<LearnerRegistration> registrations = {
      {&MpcFamily(),
       [](const TrainConfig& config, const LearnerInputs& inputs) -> std::unique_ptr<Learner> {
         return std::make_unique<MpcLearner>(config, inputs);
       },
       LoadMpcAgent},
      {&PolicyOptFamily(),
       [](const TrainConfig& config, const LearnerInputs& inputs) -> std::unique_ptr<Learner> {
         return std::make_unique<PolicyOptLearner>(config, inputs);
       },
       LoadPolicyOptAgent},
  };
  return registrations;
}

}  // namespace

const LearnerRegistration& RegistrationOf(const FamilySheet& family) {
  for (const LearnerRegistration& registration : Registrations()) {
    if (registration.family == &family) return registration;
  }
  Fail("no learner is registered for the {} family", family.name);
}

std::unique_ptr<Learner> MakeLearner(const TrainConfig& config, const LearnerInputs& inputs) {
  return RegistrationOf(FamilyOf(config.algorithm)).make(config, inputs);
}

}  // namespace cmbrl

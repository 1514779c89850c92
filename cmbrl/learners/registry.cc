#include "cmbrl/learners/registry.h"

#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/learners/mpc/mpc_learner.h"
#include "cmbrl/learners/policy_opt/policy_opt_learner.h"

namespace cmbrl {
namespace {

const std::vector<LearnerRegistration>& Registrations() {
  static const std::vector<LearnerRegistration> registrations = {
      {LearnerFamily::kMpc,
       [](const TrainConfig& config) -> std::unique_ptr<Learner> {
         return std::make_unique<MpcLearner>(config);
       },
       [] { return ProgressCsvHeader(); }},
      {LearnerFamily::kPolicyOptimisation,
       [](const TrainConfig& config) -> std::unique_ptr<Learner> {
         return std::make_unique<PolicyOptLearner>(config);
       },
       [] { return ProgressHeader(PolicyOptProgressColumns()); }},
  };
  return registrations;
}

}  // namespace

const LearnerRegistration& RegistrationOf(LearnerFamily family) {
  for (const LearnerRegistration& registration : Registrations()) {
    if (registration.family == family) return registration;
  }
  Fail("no learner is registered for this family");
}

std::unique_ptr<Learner> MakeLearner(const TrainConfig& config) {
  return RegistrationOf(FindAlgorithm(config.algorithm).family).make(config);
}

}  // namespace cmbrl

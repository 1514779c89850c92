// The learners by family: what builds the learner of a run's algorithm. The algorithms
// themselves, with their names, labels and families, are listed once in run/algorithms.h, and
// what the rest of cmbrl knows of a family in its sheet (run/learner_family.h), both free of
// LibTorch for reports and sweeps; this adds what needs the learners' code. As MuJoCo MPC lists
// its planners in one file, a new algorithm is a line there and, for a new family, a sheet and
// an entry here; the registry test builds every algorithm's learner.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "cmbrl/config/config.h"
#include "cmbrl/learners/learner_inputs.h"
#include "cmbrl/run/algorithms.h"
#include "cmbrl/run/learner.h"

namespace cmbrl {

class Env;
class Policy;
struct MpcParts;

// A trained run's acting parts, loaded from its checkpoint: an environment of its task and the
// policy that acts in it; for an MPC run also the models behind its agent (`mpc`, whose env and
// agent `env` and `policy` then point into).
struct TrainedAgent {
  TrainedAgent();
  ~TrainedAgent();
  TrainedAgent(TrainedAgent&&) noexcept;
  TrainedAgent& operator=(TrainedAgent&&) noexcept;

  Env* env = nullptr;
  Policy* policy = nullptr;
  std::unique_ptr<MpcParts> mpc;  // MPC runs only
  std::unique_ptr<Env> owned_env;  // model-free runs: what env and policy point to
  std::unique_ptr<Policy> owned_policy;
};

struct LearnerRegistration {
  const FamilySheet* family;
  // Builds a fresh learner for a validated config (a run's start, or its resume before Load).
  std::function<std::unique_ptr<Learner>(const TrainConfig&, const LearnerInputs&)> make;
  // Loads what acts for a trained run from its checkpoint folder, building only that (a
  // model-free run's policy network, not its learner); `seed` seeds the environment and, for
  // MPC, the planner. Throws cmbrl::Error naming a missing or damaged file.
  std::function<TrainedAgent(const TrainConfig&, const std::filesystem::path& checkpoint_dir,
                             std::uint64_t seed, const LearnerInputs&)>
      load_agent;
};

// The registration of a family; every family has one.
const LearnerRegistration& RegistrationOf(const FamilySheet& family);

// The learner that trains `config.algorithm`; throws cmbrl::Error naming an unknown algorithm,
// or a part the run needs that `inputs` lacks.
std::unique_ptr<Learner> MakeLearner(const TrainConfig& config, const LearnerInputs& inputs = {});

}  // namespace cmbrl

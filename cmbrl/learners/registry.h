// The learners by family: what builds the learner of a run's algorithm. The algorithms
// themselves, with their names, labels and families, are listed once in run/algorithms.h (free
// of LibTorch, for reports and sweeps); this adds what needs the learners' code. As MuJoCo MPC
// lists its planners in one file, a new algorithm is a line there and, for a new family, an
// entry here; the registry test builds every algorithm's learner.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "cmbrl/config/config.h"
#include "cmbrl/run/algorithms.h"
#include "cmbrl/run/learner.h"

namespace cmbrl {

struct LearnerRegistration {
  LearnerFamily family;
  // Builds a fresh learner for a validated config (a run's start, or its resume before Load).
  std::function<std::unique_ptr<Learner>(const TrainConfig&)> make;
  // The header line of its progress.csv (its columns, in order).
  std::function<std::string()> progress_header;
};

// The registration of a family; every family has one.
const LearnerRegistration& RegistrationOf(LearnerFamily family);

// The learner that trains `config.algorithm`; throws cmbrl::Error naming an unknown algorithm.
std::unique_ptr<Learner> MakeLearner(const TrainConfig& config);

}  // namespace cmbrl

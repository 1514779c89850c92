// What a learner may be given beside its config by the program that trains or loads the run:
// parts that a config file cannot hold (Python functions). Empty from the command line.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace cmbrl {

class RewardTerm;
class TerminationTerm;

struct LearnerInputs {
  // The planning objective's reward term of a run whose objective.reward is "python".
  std::function<std::unique_ptr<RewardTerm>()> python_reward;
  // Its termination term, where objective.termination is "python".
  std::function<std::unique_ptr<TerminationTerm>()> python_termination;
  // The functions given, "reward=module.f, termination=module.g": each session records them.
  std::string python_functions;
};

}  // namespace cmbrl

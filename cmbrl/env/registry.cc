#include "cmbrl/env/registry.h"

#include "cmbrl/env/goal_env.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

std::vector<std::string> EnvNames() { return GoalTaskNames(); }

std::unique_ptr<Env> MakeEnv(const std::string& task, Variant variant) {
  return std::make_unique<GoalEnv>(GoalTaskSpecByName(task, variant));
}

}  // namespace cmbrl

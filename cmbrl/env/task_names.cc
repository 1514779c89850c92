// The task names of registry.h, apart from the factory so that sweeps and reports can list the
// tasks without linking MuJoCo.
#include "cmbrl/env/registry.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

std::vector<std::string> EnvNames() { return GoalTaskNames(); }

}  // namespace cmbrl

// The MJCF document of a Goal world (facts A1, B0): floor, robot, goal, hazards and vases.
#pragma once

#include <string>

#include "cmbrl/env/robots/robot.h"
#include "cmbrl/env/tasks/task_spec.h"

namespace cmbrl {

// Positions are placeholders; NavigationEnv places objects at every reset. Thread-safe (pure).
std::string BuildNavigationWorldMjcf(const NavigationTaskSpec& spec, const RobotDescription& robot);

}  // namespace cmbrl

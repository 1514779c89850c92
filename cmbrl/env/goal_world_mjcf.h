// The MJCF document of a Goal world (facts A1, B0): floor, robot, goal, hazards and vases.
#pragma once

#include <string>

#include "cmbrl/env/robots/robot.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

// Positions are placeholders; GoalEnv places objects at every reset. Thread-safe (pure).
std::string BuildGoalWorldMjcf(const GoalTaskSpec& spec, const RobotDescription& robot);

}  // namespace cmbrl

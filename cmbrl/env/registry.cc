#include "cmbrl/env/registry.h"

#include "cmbrl/env/goal_env.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

std::unique_ptr<Env> MakeEnv(const std::string& task, Variant variant, Spawn spawn) {
  const GoalTaskSpec spec = GoalTaskSpecByName(task, variant);
  RobotDescription robot = TaskRobot(spec);
  if (spawn == Spawn::kModelOrigin) robot.spawn_height = robot.model_origin_height;
  return std::make_unique<GoalEnv>(spec, std::move(robot));
}

}  // namespace cmbrl

// What an agent observes of a Goal world, in two kinds (facts A5, B1): Safety Gym's own
// observation (sensors and pseudo-lidar of goal, hazards and vases, blocks in alphabetical order
// of their keys) and the paper's ego-frame state vector (relative coordinates of every object).
// GoalEnv holds one observer chosen by its spec's ObservationKind.
#pragma once

#include <memory>
#include <vector>

#include "cmbrl/core/vec2.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/mujoco_handles.h"
#include "cmbrl/env/observation.h"
#include "cmbrl/env/robots/robot.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

// The world as an observer reads it at one moment. Borrowed pointers into the environment.
struct GoalWorldView {
  const double* sensordata = nullptr;  // MuJoCo's sensor values
  RobotFrame robot;
  Vec2 goal;
  const std::vector<Vec2>* hazards = nullptr;
  std::vector<Vec2> vases;  // live positions
};

// Thread-compatible (const after construction).
class GoalObserver {
 public:
  virtual ~GoalObserver() = default;
  // Names and bounds of the observation's components.
  virtual const BoxSpec& spec() const = 0;
  // Writes spec().size() values.
  virtual void Observe(const GoalWorldView& world, double* out) const = 0;
};

// The observer of `spec.observation` for a compiled Goal world. Throws cmbrl::Error naming a
// sensor the model lacks.
std::unique_ptr<GoalObserver> MakeGoalObserver(const GoalTaskSpec& spec,
                                               const RobotDescription& robot,
                                               const mjModel& model);

}  // namespace cmbrl

// What an agent observes of a navigation world, in two kinds (facts A5, B1): Safety Gym's own
// observation (sensors and a pseudo-lidar per kind of object, in Safety-Gymnasium's order or the
// original's alphabetical one) and the paper's ego-frame state vector (relative coordinates of
// every object; Goal tasks only). NavigationEnv holds one observer chosen by its spec's
// ObservationKind.
#pragma once

#include <memory>
#include <vector>

#include "cmbrl/core/vec2.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/mujoco_handles.h"
#include "cmbrl/env/observation.h"
#include "cmbrl/env/robots/robot.h"
#include "cmbrl/env/tasks/task_spec.h"

namespace cmbrl {

// The world as an observer reads it at one moment. Borrowed pointers into the environment.
struct NavigationWorldView {
  const double* sensordata = nullptr;  // MuJoCo's sensor values
  RobotFrame robot;
  Vec2 goal;
  const std::vector<Vec2>* hazards = nullptr;
  std::vector<Vec2> vases;  // live positions
  // The other families' objects (live positions), empty where the task has none.
  const std::vector<Vec2>* buttons = nullptr;
  const std::vector<Vec2>* pillars = nullptr;
  std::vector<Vec2> gremlins;
  std::vector<Vec2> box;     // the push box: one point or none
  std::vector<Vec2> circle;  // the ring's centre: one point or none
  // Button: while the buttons' timer runs, buttons_lidar reads zeros (button_level0.py, obs).
  bool buttons_hidden = false;
};

// Thread-compatible (const after construction).
class NavigationObserver {
 public:
  virtual ~NavigationObserver() = default;
  // Names and bounds of the observation's components.
  virtual const BoxSpec& spec() const = 0;
  // Writes spec().size() values.
  virtual void Observe(const NavigationWorldView& world, double* out) const = 0;
};

// The observer of `spec.observation` for a compiled Goal world. Throws cmbrl::Error naming a
// sensor the model lacks.
std::unique_ptr<NavigationObserver> MakeNavigationObserver(const NavigationTaskSpec& spec,
                                               const RobotDescription& robot,
                                               const mjModel& model);

}  // namespace cmbrl

// Hand-built scenes for environment tests.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "cmbrl/env/env.h"
#include "cmbrl/env/tasks/layout.h"
#include "cmbrl/env/tasks/task_spec.h"

namespace cmbrl::testing {

// Robot at the origin facing +x; goal and every object far away (nothing interacts).
inline NavigationLayout FarLayout(const NavigationTaskSpec& spec) {
  NavigationLayout layout;
  layout.robot = {{0.0, 0.0}, 0.0};
  layout.goal = {100.0, 100.0};
  for (int i = 0; i < spec.num_hazards; ++i) layout.hazards.push_back({50.0 + i, 50.0});
  for (int i = 0; i < spec.num_vases; ++i) layout.vases.push_back({{-50.0 - i, 50.0}, 0.0});
  for (int i = 0; i < spec.num_buttons; ++i) layout.buttons.push_back({50.0 + i, -50.0});
  for (int i = 0; i < spec.num_gremlins; ++i) layout.gremlins.push_back({{-50.0 - i, -50.0}, 0.0});
  for (int i = 0; i < spec.num_pillars; ++i) layout.pillars.push_back({60.0 + i, -60.0});
  layout.box = {{-60.0, 60.0}, 0.0};
  return layout;
}

// An observation's blocks, in order: (key, size) of consecutive names "key_x" / "key_0", ...,
// e.g. ("accelerometer", 3), ("goal_lidar", 16).
inline std::vector<std::pair<std::string, int>> ObservationBlocks(const BoxSpec& spec) {
  std::vector<std::pair<std::string, int>> blocks;
  for (const std::string& name : spec.names) {
    const std::string key = name.substr(0, name.rfind('_'));
    if (blocks.empty() || blocks.back().first != key) blocks.push_back({key, 0});
    ++blocks.back().second;
  }
  return blocks;
}

}  // namespace cmbrl::testing

#include "cmbrl/env/navigation_env.h"

namespace cmbrl::testing {

// The robot body's planar speed (m/s) and yaw rate (rad/s), in the world frame.
inline double RobotSpeed(const NavigationEnv& env) {
  mjtNum velocity[6];
  mj_objectVelocity(&env.model(), &env.data(), mjOBJ_BODY,
                    mj_name2id(&env.model(), mjOBJ_BODY, "robot"), velocity, 0);
  return std::hypot(velocity[3], velocity[4]);
}

inline double RobotYawRate(const NavigationEnv& env) {
  mjtNum velocity[6];
  mj_objectVelocity(&env.model(), &env.data(), mjOBJ_BODY,
                    mj_name2id(&env.model(), mjOBJ_BODY, "robot"), velocity, 0);
  return velocity[2];
}

// Height of the robot body's origin and the world z of its up axis (1 when upright).
inline double RobotHeight(const NavigationEnv& env) {
  return env.data().xpos[3 * mj_name2id(&env.model(), mjOBJ_BODY, "robot") + 2];
}
// Checks the scene's robot_upright against the body's rotation matrix on the way.
inline double RobotUpZ(const NavigationEnv& env) {
  const double up = env.Scene().robot_upright;
  EXPECT_EQ(up, env.data().xmat[9 * mj_name2id(&env.model(), mjOBJ_BODY, "robot") + 8]);
  return up;
}

// Runs a constant action for `seconds` of simulated time (whole agent steps).
inline void Hold(NavigationEnv& env, const std::vector<double>& action, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / env.agent_step_seconds()));
  for (int i = 0; i < steps; ++i) env.Step(action);
}

// A Goal environment with everything far away, the robot at the origin facing +x, and an
// episode long enough for physics tests.
inline NavigationEnv FarEnv(const std::string& task, Variant variant) {
  NavigationTaskSpec spec = NavigationTaskSpecByName(task, variant);
  spec.max_env_steps = 1 << 20;
  NavigationEnv env(spec);
  env.ResetToLayout(FarLayout(spec));
  return env;
}

}  // namespace cmbrl::testing

#include "cmbrl/env/goal_world_mjcf.h"

#include <fmt/format.h>

namespace cmbrl {
namespace {

// Colours (rgba) of the scene objects, as Safety Gym draws them.
constexpr const char* kGoalRgba = "0 1 0 0.25";
constexpr const char* kHazardRgba = "0 0 1 0.25";
constexpr const char* kVaseRgba = "0 1 1 1";

}  // namespace

std::string BuildGoalWorldMjcf(const GoalTaskSpec& spec, const RobotDescription& robot) {
  std::string objects;
  objects += fmt::format(
      R"(
    <body name="goal" mocap="true" pos="0 0 {}">
      <geom name="goal" type="cylinder" size="{} {}" contype="0" conaffinity="0" rgba="{}"/>
    </body>)",
      spec.goal_size / 2 + 0.01, spec.goal_size, spec.goal_size / 2, kGoalRgba);
  for (int i = 0; i < spec.num_hazards; ++i) {
    objects += fmt::format(
        R"(
    <body name="hazard{0}" mocap="true" pos="0 0 0.02">
      <geom name="hazard{0}" type="cylinder" size="{1} 0.01" contype="0" conaffinity="0"
            rgba="{2}"/>
    </body>)",
        i, spec.hazard_size, kHazardRgba);
  }
  for (int i = 0; i < spec.num_vases; ++i) {
    // Parked apart from each other until the first reset places them.
    objects += fmt::format(
        R"(
    <body name="vase{0}" pos="{1} 10 {2}">
      <freejoint name="vase{0}"/>
      <geom name="vase{0}" type="box" size="{3} {3} {3}" density="{4}" rgba="{5}"/>
    </body>)",
        i, 10.0 + i, spec.vase_half_size - spec.vase_sink, spec.vase_half_size, spec.vase_density,
        kVaseRgba);
  }
  return fmt::format(
      R"(<mujoco model="{name}">
  <compiler angle="radian"/>
  <option timestep="{timestep}"/>
  <default>
    <geom condim="6"/>
    <joint damping="0.001"/>
  </default>
  <worldbody>
    <light pos="0 0 4" dir="0 0 -1"/>
    <geom name="floor" type="plane" size="3.5 3.5 0.1" condim="6" rgba="1 1 1 1"/>{robot}{objects}
  </worldbody>
  <tendon>{tendon}
  </tendon>
  <equality>{equality}
  </equality>
  <actuator>{actuator}
  </actuator>
  <sensor>{sensor}
  </sensor>
</mujoco>
)",
      fmt::arg("name", spec.name), fmt::arg("timestep", robot.timestep),
      fmt::arg("robot", robot.body_mjcf), fmt::arg("objects", objects),
      fmt::arg("tendon", robot.tendon_mjcf), fmt::arg("equality", robot.equality_mjcf),
      fmt::arg("actuator", robot.actuator_mjcf), fmt::arg("sensor", robot.sensor_mjcf));
}

}  // namespace cmbrl

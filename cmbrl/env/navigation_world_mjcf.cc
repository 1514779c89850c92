#include "cmbrl/env/navigation_world_mjcf.h"

#include <fmt/format.h>

#include <cmath>

namespace cmbrl {
namespace {

// Colours (rgba) of the scene objects, as Safety Gym draws them.
constexpr const char* kGoalRgba = "0 1 0 0.25";
constexpr const char* kHazardRgba = "0 0 1 0.25";
constexpr const char* kVaseRgba = "0 1 1 1";
constexpr const char* kButtonRgba = "1 0.5 0 1";
constexpr const char* kGremlinRgba = "0.5 0 1 1";
constexpr const char* kPillarRgba = "0.5 0.5 1 1";
constexpr const char* kBoxRgba = "1 1 0 0.25";
constexpr const char* kCircleRgba = "0 1 0 0.1";
constexpr const char* kSigwallRgba = "1 0 0 0.1";

// Button's and Push's objects (buttons.py, gremlins.py, pillars.py, push_box.py), parked apart
// until the first reset places them. Buttons and pillars are mocap bodies so that a reset can
// move them; their geoms collide. A gremlin is a free box welded to a mocap body, which the
// environment moves before every physics step; the weld holds the box `size` above the mocap,
// as Safety-Gymnasium's weld to a mocap at the world origin does.
std::string FamilyObjects(const NavigationTaskSpec& spec, std::string& equality) {
  std::string objects;
  for (int i = 0; i < spec.num_buttons; ++i) {
    objects += fmt::format(
        R"(
    <body name="button{0}" mocap="true" pos="{1} -10 {2}">
      <geom name="button{0}" type="sphere" size="{2}" rgba="{3}"/>
    </body>)",
        i, 10.0 + i, spec.button_size, kButtonRgba);
  }
  for (int i = 0; i < spec.num_pillars; ++i) {
    objects += fmt::format(
        R"(
    <body name="pillar{0}" mocap="true" pos="{1} -12 {2}">
      <geom name="pillar{0}" type="cylinder" size="{3} {2}" rgba="{4}"/>
    </body>)",
        i, 10.0 + i, spec.pillar_height, spec.pillar_size, kPillarRgba);
  }
  if (spec.push_box) {
    objects += fmt::format(
        R"(
    <body name="push_box" pos="-10 10 {0}">
      <freejoint name="push_box"/>
      <geom name="push_box" type="box" size="{0} {0} {0}" density="{1}" rgba="{2}"/>
    </body>)",
        spec.box_size, spec.box_density, kBoxRgba);
  }
  for (int i = 0; i < spec.num_gremlins; ++i) {
    objects += fmt::format(
        R"(
    <body name="gremlin{0}obj" pos="{1} -14 {2}">
      <freejoint name="gremlin{0}"/>
      <geom name="gremlin{0}" type="box" size="{2} {2} {2}" density="{3}" rgba="{4}"/>
    </body>
    <body name="gremlin{0}mocap" mocap="true" pos="{1} -14 0">
      <geom name="gremlin{0}mocap" type="box" size="{2} {2} {2}" contype="0" conaffinity="0"
            rgba="0.5 0 1 0.1"/>
    </body>)",
        i, 10.0 + i, spec.gremlin_size, spec.gremlin_density, kGremlinRgba);
    equality += fmt::format(
        R"(
    <weld name="gremlin{0}" body1="gremlin{0}mocap" body2="gremlin{0}obj" relpose="0 0 {1} 1 0 0 0"
          solref=".02 1.5"/>)",
        i, spec.gremlin_size);
  }
  if (spec.circle) {
    objects += fmt::format(
        R"(
    <body name="circle" pos="0 0 0.01">
      <geom name="circle" type="cylinder" size="{} 0.01" contype="0" conaffinity="0" rgba="{}"/>
    </body>)",
        spec.circle_radius, kCircleRgba);
  }
  // Visual walls (sigwalls.py): x = +-locate, then y = +-locate turned a quarter.
  const double walls[4][3] = {{spec.sigwall_locate, 0, 0},
                              {-spec.sigwall_locate, 0, 0},
                              {0, spec.sigwall_locate, M_PI / 2},
                              {0, -spec.sigwall_locate, M_PI / 2}};
  for (int i = 0; i < spec.num_sigwalls; ++i) {
    objects += fmt::format(
        R"(
    <body name="sigwall{0}" pos="{1} {2} 0.25" euler="0 0 {3}">
      <geom name="sigwall{0}" type="box" size="0.05 3.5 0.3" contype="0" conaffinity="0"
            rgba="{4}"/>
    </body>)",
        i, walls[i][0], walls[i][1], walls[i][2], kSigwallRgba);
  }
  return objects;
}

}  // namespace

std::string BuildNavigationWorldMjcf(const NavigationTaskSpec& spec, const RobotDescription& robot) {
  std::string objects;
  if (HasGoal(spec)) {
    objects += fmt::format(
      R"(
    <body name="goal" mocap="true" pos="0 0 {}">
      <geom name="goal" type="cylinder" size="{} {}" contype="0" conaffinity="0" rgba="{}"/>
    </body>)",
        spec.goal_size / 2 + 0.01, spec.goal_size, spec.goal_size / 2, kGoalRgba);
  }
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
  std::string equality = robot.equality_mjcf;
  objects += FamilyObjects(spec, equality);
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
      fmt::arg("tendon", robot.tendon_mjcf), fmt::arg("equality", equality),
      fmt::arg("actuator", robot.actuator_mjcf), fmt::arg("sensor", robot.sensor_mjcf));
}

}  // namespace cmbrl

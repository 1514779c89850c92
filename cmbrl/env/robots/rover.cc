#include <fmt/format.h>

#include "cmbrl/env/robots/robot.h"

namespace cmbrl {
namespace {

// One front wheel: a steering hinge carrying a thin post, an axle and two free-spinning halves.
std::string FrontWheel(const char* side, double y) {
  return fmt::format(R"(
      <body name="front-{0}-wheel" pos="0.2 {1} -0.15">
        <joint name="front-{0}-steer" type="hinge" axis="0 0 1" limited="true"
               range="-0.698132 0.698132" damping="0.01"/>
        <geom type="capsule" size="0.005" fromto="0 0 0 0 0 0.08" density="40" contype="2"
              conaffinity="2"/>
        <geom type="cylinder" size="0.01" fromto="0 -0.015 0 0 0.015 0" mass="0.125"/>
        <body name="front-{0}-wheel-a" pos="0 -0.0125 0">
          <joint name="front-{0}-spin-a" type="hinge" axis="0 1 0" damping="0.01"/>
          <geom type="cylinder" size="0.05 0.0025" zaxis="0 1 0" mass="0.125" condim="4"
                rgba="0.2 0.2 0.2 1"/>
        </body>
        <body name="front-{0}-wheel-b" pos="0 0.0125 0">
          <joint name="front-{0}-spin-b" type="hinge" axis="0 1 0" damping="0.01"/>
          <geom type="cylinder" size="0.05 0.0025" zaxis="0 1 0" mass="0.125" condim="4"
                rgba="0.2 0.2 0.2 1"/>
        </body>
      </body>)",
                     side, y);
}

// One rear drive wheel, 0.05 wide, extending outward from its hub.
std::string RearWheel(const char* side, double y) {
  const double outward = y > 0 ? 0.05 : -0.05;
  return fmt::format(R"(
      <body name="rear-{0}-wheel" pos="-0.2 {1} -0.15">
        <joint name="rear-{0}" type="hinge" axis="0 1 0" damping="0.01"/>
        <geom type="cylinder" size="0.05" fromto="0 0 0 0 {2} 0" mass="0.125" condim="4"
              rgba="0.2 0.2 0.2 1"/>
      </body>)",
                     side, y, outward);
}

}  // namespace

RobotDescription RoverRobot() {
  // Facts B0. Defaults of the paper's car.xml: density 40, condim 6, joint damping 0.001.
  RobotDescription robot;
  robot.name = "rover";
  robot.timestep = 0.02;
  robot.planar_joints = false;
  // The paper's model puts the body origin at z 0, which spawns the wheels 0.2 m below the
  // floor; see docs/ENVIRONMENTS.md and rover_spawn in navigation_env_test for what that does. We spawn
  // it standing on its wheels instead: wheel centres 0.15 below the origin, radius 0.05.
  robot.spawn_height = 0.2;
  robot.model_origin_height = 0.0;  // facts B0
  robot.footprint_radius = 0.25;
  robot.body_mjcf = R"(
    <body name="robot" pos="0 0 0">
      <freejoint name="robot"/>
      <site name="robot" pos="0 0 0" size="0.05"/>
      <geom name="rover-body" type="box" size="0.2 0.1 0.095" mass="12" density="40"
            rgba="1 0 0 1"/>
      <body name="ghost-steer" pos="0 0 0.15">
        <joint name="ghost-steer" type="hinge" axis="0 0 1" limited="true"
               range="-0.523599 0.523599" damping="0"/>
        <geom type="cylinder" size="0.05 0.005" zaxis="0 1 0" mass="0.002" contype="2"
              conaffinity="2" rgba="1 1 1 0.3"/>
      </body>)" + RearWheel("left", 0.1) +
                    RearWheel("right", -0.1) + FrontWheel("left", 0.1) + FrontWheel("right", -0.1) +
                    R"(
    </body>)";
  robot.tendon_mjcf = R"(
    <fixed name="rear-differential">
      <joint joint="rear-left" coef="1"/>
      <joint joint="rear-right" coef="1"/>
    </fixed>)";
  robot.equality_mjcf = R"(
    <joint joint1="front-left-steer" joint2="ghost-steer"
           polycoef="9.36e-5 2.00415 1.47161 -1.09297 -3.22520"
           solimp="0.995 0.999 0.0001" solref="0.01 0.75"/>
    <joint joint1="front-right-steer" joint2="ghost-steer"
           polycoef="-1.70e-4 2.00394 -1.46846 -1.09014 3.19742"
           solimp="0.995 0.999 0.0001" solref="0.01 0.75"/>)";
  robot.actuator_mjcf = R"(
    <position name="steering" joint="ghost-steer" gear="1" kp="1" ctrllimited="true"
              ctrlrange="-0.6 0.6"/>
    <motor name="throttle" tendon="rear-differential" gear="1" ctrllimited="true"
           ctrlrange="-1 1" forcelimited="true" forcerange="-1 1"/>)";
  robot.sensor_mjcf = R"(
    <accelerometer name="accelerometer" site="robot"/>
    <velocimeter name="velocimeter" site="robot"/>
    <gyro name="gyro" site="robot"/>
    <magnetometer name="magnetometer" site="robot"/>
    <subtreecom name="subtreecom" body="robot"/>
    <subtreelinvel name="subtreelinvel" body="robot"/>)";
  // The paper's contact code drops unnamed geoms, so only the chassis counts (facts B0).
  robot.vase_contact_geoms = {"rover-body"};
  robot.magnetometer_before_gyro = true;
  robot.action_names = {"steering", "throttle"};
  return robot;
}

}  // namespace cmbrl

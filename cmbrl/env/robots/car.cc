#include "cmbrl/env/robots/robot.h"

namespace cmbrl {

RobotDescription CarRobot(Variant variant) {
  return IsPaperWorld(variant) ? RoverRobot() : TwoWheelCarRobot();
}

RobotDescription TwoWheelCarRobot() {
  // Facts A6: a 0.2 x 0.2 x 0.1 box on two drive wheels at +y and a passive ball at -y, density 5
  // (about 0.03 kg). Wheel centres sit 0.05 below the body origin with radius 0.05, so the body
  // origin spawns 0.1 above the floor with all three contacts touching it.
  RobotDescription robot;
  robot.name = "car";
  robot.timestep = 0.004;
  robot.planar_joints = false;
  robot.spawn_height = 0.1;
  robot.model_origin_height = 0.1;
  robot.footprint_radius = 0.16;
  robot.body_mjcf = R"(
    <body name="robot" pos="0 0 0.1">
      <freejoint name="robot"/>
      <geom name="robot" type="box" size="0.1 0.1 0.05" density="5" rgba="1 0 0 1"/>
      <geom name="bumper" type="box" size="0.08 0.01 0.02" pos="0 -0.11 0" density="5"
            rgba="1 0.3 0.3 1"/>
      <geom name="connector" type="box" size="0.02 0.02 0.02" pos="0 -0.1 -0.04" density="5"
            rgba="1 0.3 0.3 1"/>
      <site name="robot" pos="0 0 0" size="0.05"/>
      <body name="left" pos="-0.1 0.1 -0.05">
        <joint name="left" type="hinge" axis="1 0 0"/>
        <geom name="left" type="cylinder" size="0.05 0.025" zaxis="1 0 0" density="5"
              rgba="0.2 0.2 0.2 1"/>
      </body>
      <body name="right" pos="0.1 0.1 -0.05">
        <joint name="right" type="hinge" axis="1 0 0"/>
        <geom name="right" type="cylinder" size="0.05 0.025" zaxis="1 0 0" density="5"
              rgba="0.2 0.2 0.2 1"/>
      </body>
      <body name="rear" pos="0 -0.1 -0.05">
        <joint name="rear" type="ball"/>
        <geom name="rear" type="sphere" size="0.05" density="5" rgba="0.2 0.2 0.2 1"/>
      </body>
    </body>)";
  robot.actuator_mjcf = R"(
    <motor name="left" joint="left" gear="1" ctrllimited="true" ctrlrange="-1 1"
           forcelimited="true" forcerange="-0.02 0.02"/>
    <motor name="right" joint="right" gear="1" ctrllimited="true" ctrlrange="-1 1"
           forcelimited="true" forcerange="-0.02 0.02"/>)";
  robot.sensor_mjcf = R"(
    <accelerometer name="accelerometer" site="robot"/>
    <velocimeter name="velocimeter" site="robot"/>
    <gyro name="gyro" site="robot"/>
    <magnetometer name="magnetometer" site="robot"/>
    <ballquat name="ballquat_rear" joint="rear"/>
    <ballangvel name="ballangvel_rear" joint="rear"/>)";
  robot.vase_contact_geoms = {"robot", "bumper", "connector", "left", "right", "rear"};
  robot.joint_observation_sensors = {"ballangvel_rear", "ballquat_rear"};
  robot.action_names = {"left_wheel", "right_wheel"};
  return robot;
}

}  // namespace cmbrl

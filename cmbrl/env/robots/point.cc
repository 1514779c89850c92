#include <fmt/format.h>

#include "cmbrl/env/robots/robot.h"

namespace cmbrl {

RobotDescription PointRobot(Variant variant) {
  const bool paper = IsPaperWorld(variant);
  // Facts A6 (stock) and B0 (paper's point.xml).
  const double density = paper ? 5.0 : 1.0;
  const double turn_gear = paper ? 0.5 : 0.3;
  const double turn_kv = paper ? 0.1 : 1.0;
  const double turn_force = paper ? 0.04 : 0.05;

  RobotDescription robot;
  robot.name = "point";
  robot.timestep = paper ? 0.01 : 0.002;
  robot.planar_joints = true;
  robot.spawn_height = 0.1;  // the sphere of radius 0.1 rests on the floor
  robot.model_origin_height = 0.1;
  robot.footprint_radius = 0.15;
  robot.body_mjcf = fmt::format(R"(
    <body name="robot" pos="0 0 0.1">
      <joint name="x" type="slide" axis="1 0 0" damping="0.01"/>
      <joint name="y" type="slide" axis="0 1 0" damping="0.01"/>
      <joint name="z" type="hinge" axis="0 0 1" damping="0.005"/>
      <geom name="robot" type="sphere" size="0.1" friction="1 0.01 0.01" density="{0}"
            rgba="1 0 0 1"/>
      <geom name="pointarrow" type="box" size="0.05 0.05 0.05" pos="0.1 0 0" density="{0}"
            rgba="1 0 0 1"/>
      <site name="robot" pos="0 0 0" size="0.05"/>
    </body>)",
                                density);
  robot.actuator_mjcf = fmt::format(R"(
    <motor name="thrust" site="robot" gear="0.3 0 0 0 0 0" ctrllimited="true" ctrlrange="-1 1"
           forcelimited="true" forcerange="-0.05 0.05"/>
    <velocity name="turn" joint="z" gear="{0}" kv="{1}" ctrllimited="true" ctrlrange="-1 1"
              forcelimited="true" forcerange="-{2} {2}"/>)",
                                    turn_gear, turn_kv, turn_force);
  robot.sensor_mjcf = R"(
    <accelerometer name="accelerometer" site="robot"/>
    <velocimeter name="velocimeter" site="robot"/>
    <gyro name="gyro" site="robot"/>
    <magnetometer name="magnetometer" site="robot"/>)";
  robot.vase_contact_geoms = {"robot", "pointarrow"};
  robot.action_names = {"thrust", "turn"};
  return robot;
}

}  // namespace cmbrl

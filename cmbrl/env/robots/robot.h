// The robots of the Goal tasks, as MJCF fragments plus what the task needs to know about them.
// The models are written for this project from the parameters in
// docs/FACTS.md (A6 for stock, B0 for the paper's versions).
#pragma once

#include <string>
#include <vector>

#include "cmbrl/env/variant.h"

namespace cmbrl {

// Everything the Goal world needs to place, actuate and observe one robot. Every robot has a
// body named "robot" carrying a site named "robot" with the sensors "accelerometer",
// "velocimeter", "gyro" and "magnetometer".
struct RobotDescription {
  std::string name;               // "point", "car" or "rover"
  double timestep = 0.0;          // physics step (s)
  std::string body_mjcf;          // the <body name="robot"> element and its subtree
  std::string actuator_mjcf;      // children of <actuator>, in action order
  std::string tendon_mjcf;        // children of <tendon> (may be empty)
  std::string equality_mjcf;      // children of <equality> (may be empty)
  std::string sensor_mjcf;        // children of <sensor>
  bool planar_joints = false;     // slide "x", slide "y", hinge "z"; otherwise a free joint "robot"
  double spawn_height = 0.0;      // z of the robot body's origin at reset (m)
  // z of the body's origin in the original's model file, where Safety Gym spawned it (m). The
  // rover's is 0, which puts its wheels 0.2 m into the floor (docs/ENVIRONMENTS.md).
  double model_origin_height = 0.0;
  double footprint_radius = 0.0;  // radius of a disc covering the footprint, for pictures (m)
  // Robot geoms whose contact with a vase counts as a violation.
  std::vector<std::string> vase_contact_geoms;
  // Extra sensors of the stock lidar observation ("ballquat_*" become a 3x3 matrix), in
  // Safety-Gymnasium's order: joint velocities (hinge, then ball) before positions (hinge, then
  // ball quaternions).
  std::vector<std::string> joint_observation_sensors;
  // Paper state vector: the rover puts the magnetometer before gyro z (facts B1).
  bool magnetometer_before_gyro = false;
  std::vector<std::string> action_names;  // one per actuator
};

// Point: a sphere pushed along its heading and turned by a velocity servo. The paper's version
// has timestep 0.01, density 5 and a softer turning servo.
RobotDescription PointRobot(Variant variant);

// Car: the stock two-wheel differential-drive car, or, in the paper variant, the four-wheel
// Ackermann rover that replaced it.
RobotDescription CarRobot(Variant variant);

// The stock two-wheel car (facts A6): drives toward body -y on positive wheel torques.
RobotDescription TwoWheelCarRobot();

// The paper's four-wheel Ackermann rover (facts B0): drives toward body +x on positive throttle.
RobotDescription RoverRobot();

}  // namespace cmbrl

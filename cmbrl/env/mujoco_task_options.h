// A task declared as data (config section mujoco_task): a user's MJCF model, what the agent
// observes, when a step violates the constraint, its reward, the episode and the reset. Plain
// data beside its checks, so that configuration reads it without MuJoCo; env/mujoco_task.h
// builds the environment and checks every name against the model. docs/CUSTOM_TASKS.md.
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

struct MujocoTaskOptions {
  // The MJCF file ("" for a task that is not declared). A relative path in a config file is
  // taken from that file's folder and written back absolute.
  std::string model;
  // The observation: these MuJoCo sensors' values, in this order (components
  // "<sensor>_0", "<sensor>_1", ...).
  std::vector<std::string> sensors;
  // Optional pseudo-lidar after the sensors, built as the Goal world builds its own (Safety Gym's,
  // env/observation.h): seen from body lidar_body's frame, one block of lidar_bins values per
  // group "name:body1,body2" of lidar_groups (components "<name>_lidar_0", ...), each body
  // read at its position's distance, up to lidar_max_dist metres.
  std::string lidar_body;
  std::vector<std::string> lidar_groups;
  int lidar_bins = 16;
  double lidar_max_dist = 3.0;
  // The cost (0/1; the classifier learns it, the planner never sees it): a contact of any of
  // cost_geoms with any of cost_contact_with (any geom where that is empty); or, with
  // cost_site set, that site inside any of cost_regions (geoms: sphere, box, cylinder or
  // capsule, tested by their shape).
  std::vector<std::string> cost_geoms;
  std::vector<std::string> cost_contact_with;
  std::string cost_site;
  std::vector<std::string> cost_regions;
  // The reward, one of ObservationRewardForms() computed on the observation (so that the
  // planner computes the same on predicted ones), reading the components of reward_sensor:
  //   site-distance: minus the distance of the sensor's values (a framepos: 3) to
  //                  reward_target (as many values);
  //   speed-along:   the sensor's component reward_axis (a velocimeter's, say);
  //   height:        minus |component reward_axis - reward_target[0]|.
  std::string reward = "site-distance";
  std::string reward_sensor;
  std::vector<double> reward_target;
  int reward_axis = 0;
  int episode_steps = 200;  // agent steps; then the episode is truncated
  int action_repeat = 1;    // physics steps per agent step (the model's own timestep each)
  // At each reset, joint reset_joints[i] (hinge or slide) starts uniformly in
  // [reset_low[i], reset_high[i]] added to its reference position; others at theirs, all at rest.
  std::vector<std::string> reset_joints;
  std::vector<double> reset_low;
  std::vector<double> reset_high;
};

// A lidar group "name:body1,body2" split into its name and bodies; throws cmbrl::Error naming
// an entry of another form.
struct LidarGroup {
  std::string name;
  std::vector<std::string> bodies;
};
LidarGroup ParseLidarGroup(const std::string& entry);

// The reward forms a declared task may name.
std::vector<std::string> ObservationRewardForms();

// Whether `options` declares a task (model is set).
inline bool IsDeclaredTask(const MujocoTaskOptions& options) { return !options.model.empty(); }

// Throws cmbrl::Error naming the first field with a bad value that can be told without the model
// (lengths that differ, an unknown form, a non-positive length); env/mujoco_task.h checks the
// names against the model.
void ValidateMujocoTaskOptions(const MujocoTaskOptions& options);

}  // namespace cmbrl

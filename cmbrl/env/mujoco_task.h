// The environment of a task declared as data (mujoco_task.h's options): the user's MJCF model,
// observed through named sensors, with a 0/1 cost from named contacts or a site inside named
// regions, a reward of one declared form, a fixed episode length and a reset of named joints.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/mujoco_handles.h"
#include "cmbrl/env/mujoco_task_options.h"

namespace cmbrl {

// Actions are [-1, 1] per actuator, mapped linearly onto each actuator's ctrlrange. Not
// thread-safe; distinct instances may run on distinct threads.
class MujocoTaskEnv final : public Env {
 public:
  // Loads options.model and checks every name in `options` against it. Throws cmbrl::Error
  // naming the key and the name for a sensor, geom, site or joint the model lacks (listing the
  // model's), an actuator without a ctrlrange, and MuJoCo's message for a model it refuses.
  MujocoTaskEnv(MujocoTaskOptions options, std::string task);

  std::vector<double> Reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult Step(const std::vector<double>& action) override;
  const BoxSpec& observation_spec() const override { return observation_spec_; }
  const BoxSpec& action_spec() const override { return action_spec_; }
  int max_episode_steps() const override { return options_.episode_steps; }
  double agent_step_seconds() const override;
  std::string GeneratorState() const override;
  void SetGeneratorState(const std::string& state) override;
  std::string State() const override;
  void SetState(const std::string& state) override;

 private:
  // The constructor's parts: the observed sensors and the reward's place among them; the
  // lidar's bodies; the cost's geoms, site and regions. Each throws naming a name the model
  // lacks.
  void ResolveSensors();
  void ResolveLidar();
  void ResolveCost();
  std::vector<double> Observe() const;
  bool Violated() const;  // in the state mjData holds now
  bool SiteInRegion(int region) const;

  MujocoTaskOptions options_;
  std::string task_;
  MjModelPtr model_;
  MjDataPtr data_;
  BoxSpec observation_spec_, action_spec_;
  std::vector<int> sensors_;                 // sensor ids, observation order
  int lidar_body_ = -1;                      // body id the lidar sees from
  std::vector<std::vector<int>> lidar_groups_;  // body ids per group, observation order
  std::vector<int> cost_geoms_, cost_with_;  // geom ids
  int cost_site_ = -1;
  std::vector<int> cost_regions_;             // geom ids
  int reward_offset_ = 0, reward_width_ = 0;  // reward_sensor's place in the observation
  std::vector<int> reset_qpos_;               // qpos addresses of reset_joints
  Rng rng_;
  int steps_ = 0;
};

// The reward of the declared form on the values of its sensor (`values`, `width` of them) as
// MujocoTaskOptions says; the planner's ObservationRewardTerm computes the same on tensors.
double ObservationReward(const MujocoTaskOptions& options, const double* values, int width);

}  // namespace cmbrl

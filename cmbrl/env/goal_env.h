// The Safety Gym Goal task on MuJoCo: a robot drives to a goal among hazards and vases
// (paper Section V-A; numbers in docs/FACTS.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/goal_observer.h"
#include "cmbrl/env/goal_world_mjcf.h"
#include "cmbrl/env/scene.h"
#include "cmbrl/env/mujoco_handles.h"
#include "cmbrl/env/observation.h"
#include "cmbrl/env/robots/robot.h"
#include "cmbrl/env/tasks/goal_layout.h"
#include "cmbrl/env/tasks/goal_spec.h"

namespace cmbrl {

// The task's own robot: PointRobot or CarRobot of the spec's variant.
RobotDescription TaskRobot(const GoalTaskSpec& spec);

// One Goal environment. An agent step writes the clipped action to the actuators and runs
// action_repeat env steps of frame_skip physics steps each; an env step computes reward
// (progress to the goal, +1 when reached) and cost terms, and relocates a reached goal. The
// agent step's reward is the sum over its env steps and its cost the 0/1 indicator of any
// violation; with action repeat the loop stops early when the goal is reached (the paper's
// wrapper). Not thread-safe; owns its model, data and generator.
class GoalEnv final : public Env, public SceneSource {
 public:
  // The task's own robot (PointRobot or CarRobot of the spec's variant).
  explicit GoalEnv(GoalTaskSpec spec);

  // Another robot description: a variation of a stock one (another spawn height, another
  // actuator) or a new robot that follows the conventions of RobotDescription.
  GoalEnv(GoalTaskSpec spec, RobotDescription robot);

  std::vector<double> Reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult Step(const std::vector<double>& action) override;

  const BoxSpec& observation_spec() const override { return observer_->spec(); }
  const BoxSpec& action_spec() const override { return action_spec_; }
  int max_episode_steps() const override;
  double agent_step_seconds() const override;
  SceneState Scene() const override;
  const SceneSource* scene_source() const override { return this; }
  std::string GeneratorState() const override;
  void SetGeneratorState(const std::string& state) override;
  std::string State() const override;
  void SetState(const std::string& state) override;

  // Starts an episode from a given layout instead of a sampled one (scenario tests, pictures of
  // chosen situations). Positions are used as given; the generator is not touched.
  std::vector<double> ResetToLayout(const GoalLayout& layout);

  // Moves the goal (the layout keeps everything else) without starting a new episode.
  void MoveGoal(Vec2 goal);

  const GoalTaskSpec& spec() const { return spec_; }
  const RobotDescription& robot() const { return robot_; }
  const mjModel& model() const { return *model_; }
  const mjData& data() const { return *data_; }
  int env_steps() const { return env_steps_; }  // env steps since the reset

 private:
  // What one env step produced.
  struct EnvStepOutcome {
    double reward = 0.0;
    double cost_hazards = 0.0;
    double cost_vases_contact = 0.0;
    double cost_vases_velocity = 0.0;
    bool goal_met = false;
    bool physics_error = false;
    bool goal_resample_failed = false;
  };

  EnvStepOutcome EnvStep();
  void PlaceLayout(const GoalLayout& layout);
  void ComputeCostTerms(EnvStepOutcome& outcome) const;
  std::vector<double> Observe() const;
  RobotFrame Frame() const;
  Vec2 RobotXY() const;
  Vec2 VaseXY(int vase) const;
  double DistanceToGoal() const;
  int PhysicsWarningCount() const;
  void BuildSpecs();

  GoalTaskSpec spec_;
  RobotDescription robot_;
  MjModelPtr model_;
  MjDataPtr data_;
  Rng rng_;
  GoalLayout layout_;  // hazards and goal as placed; robot and vases as of the last relocation
  BoxSpec action_spec_;

  // Ids and addresses into the model, resolved once.
  int robot_body_ = -1;
  int goal_mocap_ = -1;
  std::vector<int> hazard_mocaps_;
  std::vector<int> vase_bodies_;
  std::vector<int> vase_qpos_;
  std::vector<int> vase_geoms_;
  std::vector<int> robot_contact_geoms_;
  std::array<int, 3> planar_qpos_{-1, -1, -1};  // x, y, yaw (planar robots)
  int free_qpos_ = -1;                          // free joint (other robots)
  std::unique_ptr<GoalObserver> observer_;  // the spec's observation kind

  double last_goal_distance_ = 0.0;
  int env_steps_ = 0;
  bool episode_over_ = true;
};

}  // namespace cmbrl

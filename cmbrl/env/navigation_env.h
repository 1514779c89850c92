// Safety-Gymnasium's navigation tasks on MuJoCo: Goal (a robot drives to a goal among hazards and
// vases; paper Section V-A, numbers in docs/FACTS.md), Button, Push and Circle (docs/ENVIRONMENTS.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/env.h"
#include "cmbrl/env/navigation_observer.h"
#include "cmbrl/env/navigation_world_mjcf.h"
#include "cmbrl/env/scene.h"
#include "cmbrl/env/mujoco_handles.h"
#include "cmbrl/env/observation.h"
#include "cmbrl/env/robots/robot.h"
#include "cmbrl/env/tasks/layout.h"
#include "cmbrl/env/tasks/task_spec.h"

namespace cmbrl {

// The task's own robot: PointRobot or CarRobot of the spec's variant.
RobotDescription TaskRobot(const NavigationTaskSpec& spec);

// One navigation environment. An agent step writes the clipped action to the actuators and runs
// action_repeat env steps of frame_skip physics steps each (gremlins moved before each physics
// step); an env step computes the family's reward (Goal, Button: progress to the goal, +1 when
// reached; Push: the robot's progress to the box and the box's to the goal, +1 when there;
// Circle: speed around the ring) and every cost term, then handles a reached goal (a new goal, or
// a new goal button). The agent step's reward is the sum over its env steps and its cost the 0/1
// indicator of any violation; with action repeat the loop stops early when the goal is reached
// (the paper's wrapper). Not thread-safe; owns its model, data and generator.
class NavigationEnv final : public Env, public SceneSource {
 public:
  // The task's own robot (PointRobot or CarRobot of the spec's variant).
  explicit NavigationEnv(NavigationTaskSpec spec);

  // Another robot description: a variation of a stock one (another spawn height, another
  // actuator) or a new robot that follows the conventions of RobotDescription.
  NavigationEnv(NavigationTaskSpec spec, RobotDescription robot);

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
  // chosen situations). Positions are used as given; the generator is not touched, except that a
  // Button task draws its goal button (pass `goal_button` to choose it).
  std::vector<double> ResetToLayout(const NavigationLayout& layout,
                                    std::optional<int> goal_button = std::nullopt);

  // Moves the goal (the layout keeps everything else) without starting a new episode.
  void MoveGoal(Vec2 goal);

  const NavigationTaskSpec& spec() const { return spec_; }
  const RobotDescription& robot() const { return robot_; }
  const mjModel& model() const { return *model_; }
  const mjData& data() const { return *data_; }
  int env_steps() const { return env_steps_; }  // env steps since the reset
  int goal_button() const { return goal_button_; }    // Button: the button to press
  int button_timer() const { return button_timer_; }  // Button: steps until buttons count

 private:
  // What one env step produced.
  struct EnvStepOutcome {
    double reward = 0.0;
    StepInfo info;  // this env step's cost terms, goal_met and physics_error
    bool goal_resample_failed = false;
  };

  EnvStepOutcome EnvStep();
  void PlaceLayout(const NavigationLayout& layout);
  void MoveGremlins();
  void ComputeCostTerms(StepInfo& terms) const;
  // Contacts of a robot geom with one of `geoms`, except `skip` (-1: none).
  int RobotContacts(const std::vector<int>& geoms, int skip = -1) const;
  double FamilyReward(bool goal_met);
  bool GoalAchieved() const;
  // After a goal: a new goal (Goal, Push) or goal button (Button); false when none fits.
  bool UpdateWorld();
  void ChooseGoalButton();
  void ResetDistances();
  std::array<double, 3> BodyPosition(int body) const;
  std::array<double, 3> GoalPosition() const;  // the goal body's centre
  std::vector<double> Observe() const;
  RobotFrame Frame() const;
  Vec2 RobotXY() const;
  Vec2 VaseXY(int vase) const;
  double DistanceToGoal() const;
  double CircleReward() const;
  int PhysicsWarningCount() const;
  void BuildSpecs();

  NavigationTaskSpec spec_;
  RobotDescription robot_;
  MjModelPtr model_;
  MjDataPtr data_;
  Rng rng_;
  NavigationLayout layout_;  // hazards and goal as placed; robot and vases as of the last relocation
  BoxSpec action_spec_;

  // Ids and addresses into the model, resolved once.
  int robot_body_ = -1;
  int goal_mocap_ = -1;
  std::vector<int> hazard_mocaps_;
  std::vector<int> vase_bodies_;
  std::vector<int> vase_qpos_;
  std::vector<int> vase_geoms_;
  std::vector<int> robot_contact_geoms_;
  std::vector<int> button_mocaps_, button_geoms_;
  std::vector<int> pillar_mocaps_, pillar_geoms_;
  std::vector<int> gremlin_mocaps_, gremlin_bodies_, gremlin_qpos_, gremlin_geoms_;
  int box_body_ = -1;
  int box_qpos_ = -1;
  std::array<int, 3> planar_qpos_{-1, -1, -1};  // x, y, yaw (planar robots)
  int free_qpos_ = -1;                          // free joint (other robots)
  std::unique_ptr<NavigationObserver> observer_;  // the spec's observation kind

  double last_goal_distance_ = 0.0;
  double last_box_distance_ = 0.0;       // Push: robot to box (3-D)
  double last_box_goal_distance_ = 0.0;  // Push: box to goal (3-D)
  int goal_button_ = -1;
  int button_timer_ = 0;
  int env_steps_ = 0;
  bool episode_over_ = true;
};

}  // namespace cmbrl

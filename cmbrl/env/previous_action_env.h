// The previous action as part of the observation (config key environment.previous_action).
//
// A robot whose motion depends on its actuators' state (the Car's wheels and steering respond to
// the last controls over more than one step) is not fully observed by its sensors alone:
// experiments/cpu-grid/car-motion/hidden-state.md measured the previous action explaining about
// half of the Car's unexplained lateral move and heading change, and none of the Point's. This
// wrapper appends the action the environment last ran to every observation, so that the learned
// dynamics and the classifier see it; ActionEchoDynamics (models/) then writes the planned
// action into those components of each predicted state instead of the network's estimate.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/env/env.h"

namespace cmbrl {

// The name of the appended component for action component i: "previous_action_<i>".
std::string PreviousActionName(int i);

// Where the previous action's A components start in an observation box, or -1 where the box has
// none (no component is called previous_action_0). Throws cmbrl::Error for a box whose
// previous_action_<i> components are not A in a row.
int PreviousActionOffset(const BoxSpec& observation, int action_dim);

// Wraps an environment: its observation followed by A components, the action the last step ran
// (the agent's action clipped to the action box, as the environment clips it), zeros after a
// reset. Everything else is the wrapped environment's. Not thread-safe, as any Env.
class PreviousActionEnv final : public Env {
 public:
  // Throws cmbrl::Error for a null environment or one whose observation already ends with the
  // previous action (wrapped twice).
  explicit PreviousActionEnv(std::unique_ptr<Env> env);

  std::vector<double> Reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult Step(const std::vector<double>& action) override;

  const BoxSpec& observation_spec() const override { return observation_spec_; }
  const BoxSpec& action_spec() const override { return env_->action_spec(); }
  int max_episode_steps() const override { return env_->max_episode_steps(); }
  double agent_step_seconds() const override { return env_->agent_step_seconds(); }
  const SceneSource* scene_source() const override { return env_->scene_source(); }
  std::string GeneratorState() const override { return env_->GeneratorState(); }
  void SetGeneratorState(const std::string& state) override { env_->SetGeneratorState(state); }
  // The wrapped environment's state with the previous action; SetState refuses, changing
  // nothing, bytes that are not such a state or hold another number of actions.
  std::string State() const override;
  void SetState(const std::string& state) override;
  std::optional<std::string> TryState() const override;
  bool binary_cost() const override { return env_->binary_cost(); }
  std::optional<RgbFrame> Frame() override { return env_->Frame(); }

  const std::vector<double>& previous_action() const { return previous_; }  // (A)

 private:
  std::vector<double> Observed(std::vector<double> observation) const;
  std::string StateWith(const std::string& wrapped_state) const;

  std::unique_ptr<Env> env_;
  BoxSpec observation_spec_;
  std::vector<double> previous_;  // (A): the last step's clipped action, zeros after a reset
};

}  // namespace cmbrl

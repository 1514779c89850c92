// A Python environment as cmbrl's Env, so that the C++ learners train on it (cmbrl.train(env=...)).
// It takes Gymnasium's protocol: reset(seed=...) -> (observation, info), and step(action) with
// Safety-Gymnasium's six values (observation, reward, cost, terminated, truncated, info) or
// Gymnasium's five with the cost in info["cost"]. Observation and action spaces are 1-D Boxes; the
// action box is finite and seen by cmbrl as [-1, 1] per component (mapped linearly onto the env's
// bounds, exactly the identity where they are -1 and 1).
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/env/env.h"

namespace cmbrl::python {

namespace py = pybind11;

// Holds the GIL only inside each call: the learners call it with the GIL released, from any
// thread. Not thread-safe (as Env).
class PythonEnv final : public Env {
 public:
  // `env`: the Python environment; `name`: what made it ("mypackage.make_arm(links=2)"), for
  // messages. Throws cmbrl::Error naming the space that is not a 1-D Box of reals (or an action
  // box that is not finite). Call with the GIL held.
  PythonEnv(py::object env, std::string name);
  ~PythonEnv() override;

  std::vector<double> Reset(std::optional<std::uint64_t> seed) override;
  // The env's step on the action mapped onto its box. A violation is a cost above 0 (the raw
  // cost is in info.raw_cost). Safety-Gymnasium's info keys goal_met (a step that jumps, which
  // the dynamics do not learn) and the cost_* terms of StepInfo (cost_hazards, cost_buttons, ...) fill
  // info's fields where the env gives them. Throws cmbrl::Error naming the episode and step for an
  // exception the env raises, a result of another form, or a non-finite observation, reward or
  // cost.
  StepResult Step(const std::vector<double>& action) override;
  const BoxSpec& observation_spec() const override { return observation_spec_; }
  const BoxSpec& action_spec() const override { return action_spec_; }
  int max_episode_steps() const override { return max_episode_steps_; }
  bool binary_cost() const override { return false; }
  double agent_step_seconds() const override { return step_seconds_; }

  // The whole environment through pickle: GeneratorState is its text form ("" where it does not
  // pickle, and then restoring it changes nothing); State throws cmbrl::Error naming why it does
  // not pickle, TryState gives nothing.
  std::string GeneratorState() const override;
  void SetGeneratorState(const std::string& state) override;
  std::string State() const override;
  void SetState(const std::string& state) override;
  std::optional<std::string> TryState() const override;
  // render() of an env whose render_mode is "rgb_array": an (H, W, 3) or (H, W, 4) uint8 array
  // (alpha dropped); nothing for another render_mode. Throws cmbrl::Error naming the env for
  // another result or an exception.
  std::optional<RgbFrame> Frame() override;

  // The env's own action for one of cmbrl's ([-1, 1] per component): what an agent's action
  // means to the env.
  std::vector<double> EnvAction(const std::vector<double>& action) const;
  // The env's own action box (action_spec() is cmbrl's [-1, 1] one).
  BoxSpec EnvActionSpec() const {
    BoxSpec box = action_spec_;
    box.low = env_low_;
    box.high = env_high_;
    return box;
  }
  // What made it, as given.
  const std::string& name() const { return name_; }

 private:
  // pickle.dumps(env) as bytes, or the exception's text in `why` when it does not pickle. GIL held.
  std::optional<std::string> Pickled(std::string* why) const;
  void Unpickle(const std::string& bytes);  // GIL held
  // Parts of a step's result, named with the episode and step where they are not what they
  // should be. GIL held.
  std::vector<double> Observation(const py::handle& value, const char* call) const;
  double Number(const py::handle& value, const char* what) const;
  bool Flag(const py::handle& value, const char* what) const;
  // The step facts that Safety-Gymnasium's info carries under these keys, where it has them:
  // the goal tasks' goal_met (a step that reached the goal, which then moves: it jumps, and the
  // dynamics do not learn it) and the per-constraint costs that progress rows count.
  void ReadKnownInfo(const py::dict& info, StepInfo& out) const;
  std::string Where() const;  // "episode 3, step 17"

  py::object env_;
  std::string name_;
  BoxSpec observation_spec_;
  BoxSpec action_spec_;                     // [-1, 1] per component
  std::vector<double> env_low_, env_high_;  // the env's action bounds
  bool identity_actions_ = false;           // the env's bounds are -1 and 1
  int max_episode_steps_ = 0;
  double step_seconds_ = 0.0;
  int episode_ = 0;       // episodes begun (Reset calls)
  int episode_step_ = 0;  // steps of the current one
};

}  // namespace cmbrl::python

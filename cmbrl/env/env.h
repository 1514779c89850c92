// The environment interface, in the spirit of Gymnasium / Safety-Gymnasium: Reset gives the first
// observation, Step gives observation, reward, cost, terminated, truncated and info.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/check.h"

namespace cmbrl {

class SceneSource;  // scene.h

// A box of real vectors: component i lies in [low[i], high[i]] (infinite where unbounded).
struct BoxSpec {
  std::vector<double> low;
  std::vector<double> high;
  std::vector<std::string> names;  // one per component, e.g. "goal_x", "hazards_lidar_3"

  int size() const { return static_cast<int>(low.size()); }

  // Index of the component called `name`; throws cmbrl::Error naming it when there is none.
  int IndexOf(const std::string& name) const {
    for (int i = 0; i < size(); ++i) {
      if (names[i] == name) return i;
    }
    Fail("no component named '{}' in this box", name);
  }
};

// What one Step reports beyond reward and cost. The raw cost terms are summed over the physics
// frames the step ran, before the 0/1 indicator is taken.
struct StepInfo {
  bool goal_met = false;             // the goal was reached during this step and re-sampled
  double cost_hazards = 0.0;         // sum over hazards of (hazard radius - robot distance)+
  double cost_vases_contact = 0.0;   // number of robot-vase contacts (constrained vases only)
  double cost_vases_velocity = 0.0;  // sum of vase speeds above the threshold (m/s)
  // Safety-Gymnasium's other terms (Button, Push, Circle), 0 where the task has none.
  double cost_buttons = 0.0;          // contacts with a wrong button while the buttons count
  double cost_gremlins = 0.0;         // robot-gremlin contacts
  double cost_pillars = 0.0;          // robot-pillar contacts (constrained pillars only)
  double cost_out_of_boundary = 0.0;  // env steps outside Circle's walls
  int env_steps = 0;                 // inner environment steps run (action repeat)
  bool physics_error = false;        // MuJoCo reported an unstable state; the episode ended
  // The step's cost as the environment gave it, before the 0/1 indicator (cost > 0) is taken:
  // the same as the cost for the built-in tasks, any real number for a Python environment's.
  double raw_cost = 0.0;
};

// Safety-Gymnasium's info["cost_sum"]: the sum of the step's cost terms (before the 0/1
// indicator), 1 for a step whose physics failed (its cost_exception).
inline double CostSum(const StepInfo& info) {
  return info.cost_hazards + info.cost_vases_contact + info.cost_vases_velocity +
         info.cost_buttons + info.cost_gremlins + info.cost_pillars + info.cost_out_of_boundary +
         (info.physics_error ? 1.0 : 0.0);
}

// Adds one env step's cost terms to an agent step's (the sum over its action repeat).
inline void AddCostTerms(StepInfo& total, const StepInfo& step) {
  total.cost_hazards += step.cost_hazards;
  total.cost_vases_contact += step.cost_vases_contact;
  total.cost_vases_velocity += step.cost_vases_velocity;
  total.cost_buttons += step.cost_buttons;
  total.cost_gremlins += step.cost_gremlins;
  total.cost_pillars += step.cost_pillars;
  total.cost_out_of_boundary += step.cost_out_of_boundary;
}

// A picture of an environment's state as the environment draws it: rows of RGB bytes, top row
// first (height x width x 3).
struct RgbFrame {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

struct StepResult {
  std::vector<double> observation;  // (observation_spec().size())
  double reward = 0.0;              // progress towards the goal plus goal bonus
  double cost = 0.0;                // 0 or 1: whether any constraint was violated
  bool terminated = false;          // the episode ended by itself (physics error, no goal fits)
  bool truncated = false;           // the episode hit its time limit
  StepInfo info;
};

// An episodic environment with a continuous action box, a reward and a 0/1 constraint cost.
// Implementations own their random generator; they are not thread-safe, but distinct instances
// may be used from distinct threads.
class Env {
 public:
  virtual ~Env() = default;

  // Starts an episode. With a seed, re-seeds the environment's generator first; without one,
  // continues its sequence. Returns the first observation.
  virtual std::vector<double> Reset(std::optional<std::uint64_t> seed = std::nullopt) = 0;

  // Advances one agent step. Throws cmbrl::Error for an action of the wrong size or with a
  // non-finite entry; finite out-of-range entries are clipped to the actuator ranges.
  virtual StepResult Step(const std::vector<double>& action) = 0;

  virtual const BoxSpec& observation_spec() const = 0;
  virtual const BoxSpec& action_spec() const = 0;

  // Agent steps of an episode that runs to its time limit with no step cut short (with action
  // repeat, a step that reaches the goal ends early, so such episodes have a few more).
  virtual int max_episode_steps() const = 0;

  // Simulated seconds per agent step.
  virtual double agent_step_seconds() const = 0;

  // The environment's ground truth for pictures and tests (robot pose, goal, hazards, vases),
  // or nullptr when it has none to show. Never part of what an agent observes.
  virtual const SceneSource* scene_source() const { return nullptr; }

  // The generator's state as text, for checkpoints: restoring it before Reset() reproduces the
  // layouts that would have followed. Throws cmbrl::Error for text that is not such a state.
  virtual std::string GeneratorState() const = 0;
  virtual void SetGeneratorState(const std::string& state) = 0;

  // The environment's whole state (physics, layout, episode, generator) as bytes that
  // SetState() restores exactly in an environment made the same way (task, variant, robot): its
  // next reset or step then equals this one's. Python's pickle and deepcopy use it. SetState
  // throws cmbrl::Error, changing nothing, for bytes of another environment or damaged ones.
  virtual std::string State() const = 0;
  virtual void SetState(const std::string& state) = 0;

  // State(), or nothing where this environment's state cannot be saved (a Python environment
  // that does not pickle): a checkpoint then cannot hold an episode under way.
  virtual std::optional<std::string> TryState() const { return State(); }

  // Whether the cost a step gives is the environment's own, 0 or 1 (the built-in and declared
  // tasks), or only whether its raw cost, which may be any number (info.raw_cost), is above 0
  // (a Python environment's): such runs log the raw costs too.
  virtual bool binary_cost() const { return true; }

  // The environment's own picture of its current state, where it draws one (a Python
  // environment made with render_mode "rgb_array"); nothing otherwise. Throws cmbrl::Error for
  // a picture of another form.
  virtual std::optional<RgbFrame> Frame() { return std::nullopt; }
};

}  // namespace cmbrl

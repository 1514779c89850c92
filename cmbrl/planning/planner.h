// Planners optimise action sequences against an objective that scores them (paper Section IV-B,
// Algorithm 1). A planner knows nothing of MuJoCo or networks: only the objective's scores.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/torch_util.h"
#include "cmbrl/planning/planning_options.h"

namespace cmbrl {

// Scores of N action sequences, each (N) on the planner's device. Lower is better for both.
struct ObjectiveValues {
  torch::Tensor reward_cost;      // (N) to minimise, e.g. discounted goal distance
  torch::Tensor constraint_cost;  // (N) >= 0; exactly 0 means feasible
};

// What a planner asks of the problem. Implementations may keep scratch state, so Evaluate is not
// const and an objective is not shared between threads.
class Objective {
 public:
  virtual ~Objective() = default;

  // actions (N, H, A) within the action bounds, float32 on the planner's device.
  virtual ObjectiveValues Evaluate(const torch::Tensor& actions) = 0;
};

// Per-plan figures, kept on the device until read (reading them synchronises).
struct PlanDiagnostics {
  torch::Tensor iterations;                 // () int: iterations that updated the distribution
  torch::Tensor feasible_fraction;          // () float: feasible share of the last population
  torch::Tensor infeasible_elite_fraction;  // () float: infeasible share of all elites used
  torch::Tensor best_reward_cost;  // () float: reward cost of the returned plan's best sample
  torch::Tensor nonfinite_scores;  // () bool: some sample scored NaN or infinity (model failure)
};

struct PlanResult {
  torch::Tensor action;    // (A): the first action to execute
  torch::Tensor sequence;  // (H, A): the whole plan (final mean, or best sample)
  PlanDiagnostics diagnostics;
};

// A planner. Not thread-safe: it owns its generator and, with warm start, the previous plan.
class Planner {
 public:
  virtual ~Planner() = default;

  // Optimises against `objective`; the returned action lies within the bounds.
  virtual PlanResult Plan(Objective& objective) = 0;

  // Forgets any state carried between plans (the warm-start mean); call at episode start.
  virtual void Reset() {}

  // The generator's state, for checkpoints.
  virtual torch::Tensor GeneratorState() const = 0;
  virtual void SetGeneratorState(const torch::Tensor& state) = 0;

  // What one plan passes to the next within an episode (the warm-start mean), on the host, for
  // checkpoints taken in the middle of an episode; undefined when there is none. The next plan
  // after SetCarriedState(CarriedState()) is the one that would have followed.
  virtual torch::Tensor CarriedState() const { return {}; }
  // Throws cmbrl::Error when `state` is not one this planner's CarriedState() could return.
  virtual void SetCarriedState(const torch::Tensor& state) {
    Require(!state.defined(),
            "this planner carries nothing from one plan to the next, but a "
            "carried state was given (a checkpoint of another planner?)");
  }
};

// A planner that samples on one device from one generator of its own, seeded at construction:
// its checkpoints carry that generator's state. Each of cmbrl's planners is one.
class SeededPlanner : public Planner {
 public:
  torch::Tensor GeneratorState() const final { return generator_.get_state(); }
  void SetGeneratorState(const torch::Tensor& state) final { generator_.set_state(state); }

 protected:
  // `device` as PlanningProblem::device; throws cmbrl::Error naming it when it is not a device
  // of this build and machine.
  SeededPlanner(const std::string& device, std::uint64_t seed)
      : device_(ParseDevice(device)), generator_(MakeGenerator(device_, seed)) {}

  const torch::Device& device() const { return device_; }
  at::Generator& generator() { return generator_; }

 private:
  torch::Device device_;
  at::Generator generator_;
};

}  // namespace cmbrl

// A policy maps an observation to an action. The MPC agent implements this interface too.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmbrl/core/rng.h"
#include "cmbrl/env/env.h"

namespace cmbrl {

// Chooses actions. Not thread-safe: a policy may keep state between calls.
class Policy {
 public:
  virtual ~Policy() = default;

  // Called at the start of every episode.
  virtual void BeginEpisode() {}

  // The action for an observation, inside the action spec's box.
  virtual std::vector<double> Act(const std::vector<double>& observation) = 0;
};

// Uniform random actions in the action box, from its own seeded generator.
class RandomPolicy final : public Policy {
 public:
  RandomPolicy(BoxSpec action_spec, std::uint64_t seed);
  std::vector<double> Act(const std::vector<double>& observation) override;

 private:
  BoxSpec action_spec_;
  Rng rng_;
};

// Always the zero action (the robot coasts): a baseline and a test fixture.
class ZeroPolicy final : public Policy {
 public:
  explicit ZeroPolicy(int action_size) : action_size_(action_size) {}
  std::vector<double> Act(const std::vector<double>& /*observation*/) override {
    return std::vector<double>(action_size_, 0.0);
  }

 private:
  int action_size_;
};

// Names accepted by MakePolicy.
const std::vector<std::string>& PolicyNames();

// "random" or "zero"; throws cmbrl::Error naming an unknown policy.
std::unique_ptr<Policy> MakePolicy(const std::string& name, const BoxSpec& action_spec,
                                   std::uint64_t seed);

}  // namespace cmbrl

// Several environments stepped together: batched actions in, batched results out, each
// environment on a thread of its own share, and automatic resets (Gymnasium's vector API, its
// "same-step" mode: an environment whose episode ended this step returns the first observation
// of its next episode, and its last observation aside).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "cmbrl/core/worker_pool.h"
#include "cmbrl/env/env.h"

namespace cmbrl {

// One batched step, row k for environment k.
struct VectorStep {
  std::vector<double> observations;    // (N x O): after an episode's end, its next first one
  std::vector<double> rewards, costs;  // (N)
  std::vector<std::uint8_t> terminated, truncated;  // (N) 0/1
  std::vector<double> final_observations;  // (N x O): the ended episodes' last observations
  std::vector<std::uint8_t> goal_met;      // (N) 0/1
  std::vector<double> cost_hazards, cost_vases_contact, cost_vases_velocity;  // (N)
};

// Not thread-safe; it runs its environments on a pool of threads of its own (WorkerPool: they
// spin for up to `spin` after each call, 2 ms by default, so a loop that steps again soon finds
// them awake; 0 lets them sleep at once, for loops that step rarely).
class VectorEnv {
 public:
  // Throws cmbrl::Error for no environments, environments with different specs, fewer than one
  // thread, or a spin outside 0 to 1 s.
  VectorEnv(std::vector<std::unique_ptr<Env>> envs, int threads,
            std::chrono::microseconds spin = kDefaultSpin);

  static constexpr std::chrono::microseconds kDefaultSpin{2000};

  int size() const { return static_cast<int>(envs_.size()); }
  const Env& env(int k) const { return *envs_[static_cast<size_t>(k)]; }

  // Resets every environment: with a seed, environment k gets seed + k (Gymnasium's convention);
  // without one each continues its generator. Returns the (N x O) first observations.
  std::vector<double> Reset(std::optional<std::uint64_t> seed = std::nullopt);

  // actions: (N x A) row after row. Throws cmbrl::Error for a wrong size or a non-finite action,
  // naming the environment, before any environment steps.
  VectorStep Step(const std::vector<double>& actions);

 private:
  std::vector<std::unique_ptr<Env>> envs_;
  std::unique_ptr<WorkerPool> pool_;
};

}  // namespace cmbrl

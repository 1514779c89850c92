// Several environments stepped together: batched actions in, batched results out, each
// environment on a thread of its own share (Gymnasium's vector API). Resets follow one of
// Gymnasium 1.x's autoreset modes: "same-step" (an environment whose episode ended this step
// returns the first observation of its next episode, and its last observation aside) or
// "disabled" (the caller resets the ended environments, with a mask).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/worker_pool.h"
#include "cmbrl/env/env.h"

namespace cmbrl {

// One batched step, row k for environment k.
struct VectorStep {
  // (N x O): after an episode's end, its next first one (kSameStep) or its last (kDisabled)
  std::vector<double> observations;
  std::vector<double> rewards, costs;  // (N)
  std::vector<double> raw_costs;       // (N): StepInfo::raw_cost
  std::vector<std::uint8_t> terminated, truncated;  // (N) 0/1
  std::vector<double> final_observations;  // (N x O): kSameStep: the ended episodes' last ones
  std::vector<std::uint8_t> goal_met;      // (N) 0/1
  std::vector<double> cost_hazards, cost_vases_contact, cost_vases_velocity;  // (N)
  std::vector<double> cost_buttons, cost_gremlins, cost_pillars, cost_out_of_boundary;  // (N)
  std::vector<double> cost_sums;    // (N): CostSum of each step's info
  std::vector<std::uint8_t> reset;  // (N) 0/1: kNextStep: reset by this step instead of stepped
};

// Gymnasium 1.x's AutoresetMode.
enum class Autoreset {
  // The step after an ended episode resets that environment instead of stepping it (its action
  // is not read): the next episode's first observation, reward and cost 0, neither terminated
  // nor truncated, and `reset` set for it. Gymnasium's default.
  kNextStep,
  kSameStep,  // an ended episode is followed at once by the next one's first observation
  kDisabled,  // an ended environment waits for ResetWhere; stepping it first is an error
};

// What a checkpoint needs to continue a vector: each environment's whole state (Env::State) and,
// for Autoreset::kDisabled, whether it waits for a reset.
struct VectorEnvState {
  std::vector<std::string> envs;
  std::vector<std::uint8_t> needs_reset;  // (N) 0/1
};

// Not thread-safe; it runs its environments on a pool of threads of its own (WorkerPool: they
// spin for up to `spin` after each call, 2 ms by default, so a loop that steps again soon finds
// them awake; 0 lets them sleep at once, for loops that step rarely).
class VectorEnv {
 public:
  // Throws cmbrl::Error for no environments, environments with different specs, fewer than one
  // thread, or a spin outside 0 to 1 s.
  VectorEnv(std::vector<std::unique_ptr<Env>> envs, int threads,
            std::chrono::microseconds spin = kDefaultSpin,
            Autoreset autoreset = Autoreset::kSameStep);

  static constexpr std::chrono::microseconds kDefaultSpin{2000};

  int size() const { return static_cast<int>(envs_.size()); }
  Autoreset autoreset() const { return autoreset_; }
  const Env& env(int k) const { return *envs_[static_cast<size_t>(k)]; }
  // Environment k itself, for what the vector does not batch (its generator's state, for
  // checkpoints). Stepping or resetting it behind the vector's back breaks kDisabled's checks.
  Env& env(int k) { return *envs_[static_cast<size_t>(k)]; }

  // Resets every environment: with a seed, environment k gets seed + k (Gymnasium's convention);
  // without one each continues its generator. Returns the (N x O) first observations.
  std::vector<double> Reset(std::optional<std::uint64_t> seed = std::nullopt);

  // Gymnasium 1.x's reset with a `reset_mask`: resets environment k where mask[k] is 1, with
  // seeds[k] when `seeds` is not empty (then one per environment; entries of environments not
  // reset are ignored), else continuing its generator. Returns (N x O): the reset environments'
  // first observations, zeros in the other rows. Throws cmbrl::Error for masks or seed lists of
  // another length.
  std::vector<double> ResetWhere(const std::vector<std::uint8_t>& mask,
                                 const std::vector<std::uint64_t>& seeds = {});

  // actions: (N x A) row after row. With `active` (one 0/1 per environment), only the
  // environments marked 1 step; the others keep their state, their action rows are not read and
  // their result rows are zero (an epoch whose steps do not divide evenly between the
  // environments). Throws cmbrl::Error, naming the environment, before any environment steps:
  // for a wrong size, a non-finite action, or (kDisabled) an ended environment not reset since.
  VectorStep Step(const std::vector<double>& actions, const std::vector<std::uint8_t>& active = {});

  // Adaptive threads: Step measures, every kProbeInterval steps, kProbeSteps steps on its threads
  // and kProbeSteps on the calling thread alone, and runs on whichever was faster (median step)
  // until the next measurement. On a machine whose other cores are busy, threads that wait for
  // a core can make a step slower than stepping the environments one after another; this keeps
  // the vector never much slower than that (docs/PERFORMANCE.md). Results are the same either
  // way: environments are independent. Off by default.
  void SetAdaptiveThreads(bool adaptive);
  bool adaptive_threads() const { return adaptive_; }
  bool on_threads() const { return on_pool_; }  // where Step runs now
  static constexpr std::int64_t kProbeInterval = 2048;
  static constexpr std::int64_t kProbeSteps = 16;

  // The vector's state, which SetState restores exactly in a vector made the same way: its next
  // steps and resets then equal this one's. SetState throws cmbrl::Error, changing nothing, for a
  // state of another number of environments or one that an environment refuses (Env::SetState).
  VectorEnvState State() const;
  void SetState(const VectorEnvState& state);

 private:
  std::vector<std::unique_ptr<Env>> envs_;
  std::unique_ptr<WorkerPool> pool_;
  Autoreset autoreset_;
  void RunStep(int n, const WorkerPool::Work& body);
  bool adaptive_ = false;
  bool on_pool_ = true;
  std::int64_t steps_ = 0;
  std::vector<double> probe_pool_, probe_inline_;  // seconds per step, this measurement's
  // kDisabled, kNextStep: ended and not reset since (or never reset).
  std::vector<std::uint8_t> needs_reset_;
};

}  // namespace cmbrl

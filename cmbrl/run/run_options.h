// What every run has, whatever learns in it: the streams its seed is split into, and the outer
// loop's budget and buffers. Plain data, read by config/ and the learners alike.
#pragma once

#include <cstdint>

namespace cmbrl {

// Streams of the run seed (DeriveSeed(seed, stream)), one per consumer of randomness.
enum SeedStream : std::uint64_t {
  kEnvSeedStream,
  kPretrainSeedStream,
  kEnsembleSeedStream,
  kClassifierSeedStream,
  kPlannerSeedStream,
  kRewardModelSeedStream,
  kTerminationModelSeedStream,
};

// The outer loop of Algorithm 2 (facts B6); a model-free run reads its budget only.
struct TrainingLoopOptions {
  int pretrain_episodes = 1000;      // random-action episodes before the first fit
  int pretrain_steps = 50;           // stored agent steps per pre-training episode
  int episodes_per_epoch = 10;       // MPC episodes between refits
  std::int64_t total_steps = 10000;  // budget of TotalEnvInteracts (MPC agent steps)
  int transition_capacity = 500000;  // dynamics ring buffer
  int safe_capacity = 50000;         // classifier rings
  int unsafe_capacity = 10000;
  // false (the original's run.py): a violation label is stored only for the agent steps whose
  // transition is stored, i.e. not on a step that met the goal or ended the episode (facts B4).
  // true: every agent step's next state is labelled.
  bool label_every_step = false;
};

// The largest budget of agent steps a run may have.
inline constexpr std::int64_t kMaxTotalSteps = 10'000'000'000;

}  // namespace cmbrl

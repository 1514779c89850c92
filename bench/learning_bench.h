// `cmbrl bench plan` and `cmbrl bench train`: planning steps and model fits at a config's
// settings, each figure beside the matrix-product ceiling measured in the same run. Benchmarks
// give figures; nothing here judges them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/bench_util.h"

namespace cmbrl::bench {

struct LearningBenchOptions {
  // Composed in order, later files over earlier ones, as `cmbrl train --config` composes them.
  std::vector<std::string> config_paths = {"configs/pointgoal1-rce.yaml"};
  std::string device;                  // empty: the config's
  std::vector<std::string> planners;   // empty: the config's
  std::vector<std::string> precisions; // bench plan; empty: the config's; the first is the reference
  std::vector<std::string> backends;   // bench plan; empty: the config's (crossed with precisions)
  int fit_steps = 5000;                // bench plan with several precisions: random-policy data
  int agreement_states = 8;            // start states of the action comparison
  int runs = 5;
  int transitions = 50000;             // bench train: the epoch's data
  int classifier_states = 40000;       // bench train: the classifier fit's data
  bool full_fit = false;               // bench train: also a whole fit (up to max_epochs)
  std::uint64_t seed = 0;
};

// One planning step per planner and precision, with its dynamics and classifier parts; with
// several precisions, also each later one's errors and chosen actions against the first's.
void RunPlanBench(const LearningBenchOptions& options, const FigureSink& emit);

// One dynamics training epoch, a classifier fit, and with full_fit a whole dynamics fit.
void RunTrainBench(const LearningBenchOptions& options, const FigureSink& emit);

}  // namespace cmbrl::bench

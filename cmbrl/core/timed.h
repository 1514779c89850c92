// Wall-clock accounting of a process's parts.
#pragma once

#include <chrono>

namespace cmbrl {

// Adds the seconds `work` takes to `total` (also when it throws) and returns its result.
template <typename Work>
auto Timed(double& total, Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  struct Add {
    double& total;
    std::chrono::steady_clock::time_point start;
    ~Add() {
      total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  } add{total, start};
  return work();
}

}  // namespace cmbrl

// Time accounting of a process: wall clock of its parts, and its CPU time.
#pragma once

#include <time.h>

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

// The CPU seconds the process has used so far: every thread's user and system time. Unlike the
// wall clock it stands still while the process is stopped (SIGSTOP) or waits, and it leaves out
// the time a hypervisor gave the cores to others (steal), where the kernel accounts for it.
inline double ProcessCpuSeconds() {
  timespec now{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now) != 0) return 0.0;
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace cmbrl

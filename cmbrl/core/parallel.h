// Splitting a loop over plain threads that sleep when done. The planner's BLAS threads keep
// spinning for a while after each matrix product, and a second spinning pool (OpenMP) on the
// same two cores made a planning step 1.7x slower; threads started per call do not spin.
#pragma once

#include <sched.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

namespace cmbrl {

// Calls work(begin, end) on `workers` contiguous parts of [0, count): the first part on the
// calling thread, each other on a thread of its own (a start costs tens of microseconds, so
// callers ask for several workers only for large loops). Returns when all parts are done. An
// exception thrown by a part is rethrown here once every part has ended (that of the earliest
// part when several throw).
template <typename Work>
void ParallelRanges(std::int64_t count, int workers, Work&& work) {
  if (workers <= 1 || count <= 1) {
    work(std::int64_t{0}, count);
    return;
  }
  const auto bound = [&](int worker) { return count * worker / workers; };
  std::vector<std::exception_ptr> failures(static_cast<size_t>(workers));
  const auto run_part = [&](int worker) {
    try {
      work(bound(worker), bound(worker + 1));
    } catch (...) {
      failures[static_cast<size_t>(worker)] = std::current_exception();
    }
  };
  std::vector<std::thread> helpers;
  for (int worker = 1; worker < workers; ++worker) helpers.emplace_back(run_part, worker);
  run_part(0);
  for (std::thread& helper : helpers) helper.join();
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
}

// The CPUs this process may run on, from its affinity mask (what taskset, a Slurm task or a
// sweep's share of the cores allows), in increasing order. All of the machine's when the mask
// cannot be read.
inline std::vector<int> AllowedCpus() {
  std::vector<int> cpus;
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof(mask), &mask) == 0) {
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
      if (CPU_ISSET(cpu, &mask)) cpus.push_back(cpu);
    }
  }
  if (cpus.empty()) {
    for (unsigned cpu = 0; cpu < std::max(1u, std::thread::hardware_concurrency()); ++cpu) {
      cpus.push_back(static_cast<int>(cpu));
    }
  }
  return cpus;
}

// The cores this process may use (at least 1): the machine's, or fewer where its affinity mask
// says so. Threads beyond these would only wait for one another. Cheap enough for every large
// call that splits work: one system call, no list.
inline int CoreCount() {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof(mask), &mask) == 0 && CPU_COUNT(&mask) > 0) {
    return CPU_COUNT(&mask);
  }
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace cmbrl

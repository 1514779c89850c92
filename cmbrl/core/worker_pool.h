// A fixed set of threads for loops called thousands of times a second, such as a vector of
// environments' steps. ParallelRanges (parallel.h) starts threads per call, which suits large
// loops; for a call of a millisecond, on this project's virtual machines, a new thread often
// waited for its CPU to wake, and two environments on two threads stepped only 1.1 to 1.4 times
// as fast as one (docs/PERFORMANCE.md). These workers stay alive and, between calls, spin for a
// while before they sleep, so a call that follows soon finds them awake.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace cmbrl {

// Not thread-safe: one caller at a time.
class WorkerPool {
 public:
  using Work = std::function<void(std::int64_t begin, std::int64_t end)>;

  // `threads` in all, the caller's included (threads - 1 workers). Workers spin up to `spin`
  // after each call before they sleep.
  explicit WorkerPool(int threads,
                      std::chrono::microseconds spin = std::chrono::microseconds(2000));
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // Calls work(begin, end) on threads() contiguous parts of [0, count) (empty parts skipped),
  // part 0 on the calling thread. Returns when all are done; rethrows the exception of the
  // earliest part that threw, once every part has ended.
  void Run(std::int64_t count, const Work& work);

 private:
  void Loop(int worker);
  void RunPart(int part);

  std::chrono::microseconds spin_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<std::uint64_t> generation_{0};  // one more per call
  std::atomic<int> remaining_{0};             // workers still busy with the current call
  bool stop_ = false;                         // guarded by mutex_
  const Work* work_ = nullptr;
  std::int64_t count_ = 0;
  std::vector<std::exception_ptr> failures_;
};

}  // namespace cmbrl

#include "cmbrl/core/worker_pool.h"

#include "cmbrl/core/check.h"

namespace cmbrl {

WorkerPool::WorkerPool(int threads, std::chrono::microseconds spin) : spin_(spin) {
  Require(threads >= 1, "a pool of {} threads: expected at least 1", threads);
  failures_.resize(static_cast<size_t>(threads));
  for (int worker = 1; worker < threads; ++worker)
    workers_.emplace_back([this, worker] { Loop(worker); });
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void WorkerPool::RunPart(int part) {
  const std::int64_t parts = threads();
  const std::int64_t begin = count_ * part / parts, end = count_ * (part + 1) / parts;
  if (begin >= end) return;
  try {
    (*work_)(begin, end);
  } catch (...) {
    failures_[static_cast<size_t>(part)] = std::current_exception();
  }
}

void WorkerPool::Loop(int worker) {
  std::uint64_t seen = 0;
  while (true) {
    // Spin a while for the next call, then sleep until it comes.
    const auto deadline = std::chrono::steady_clock::now() + spin_;
    while (generation_.load(std::memory_order_acquire) == seen &&
           std::chrono::steady_clock::now() < deadline) {
    }
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
      seen = generation_.load(std::memory_order_acquire);
      if (stop_) return;
    }
    RunPart(worker);
    remaining_.fetch_sub(1, std::memory_order_acq_rel);
  }
}

void WorkerPool::Run(std::int64_t count, const Work& work) {
  if (workers_.empty() || count <= 1) {
    work(0, count);
    return;
  }
  work_ = &work;
  count_ = count;
  for (std::exception_ptr& failure : failures_) failure = nullptr;
  remaining_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  RunPart(0);
  while (remaining_.load(std::memory_order_acquire) != 0) {
  }
  for (const std::exception_ptr& failure : failures_) {
    if (failure) std::rethrow_exception(failure);
  }
}

}  // namespace cmbrl

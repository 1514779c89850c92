// What the oneDNN backends (onednn_forward.cc, onednn_training.cc) share, and the benchmarks'
// oneDNN ceilings (bench/kernel_ceiling.cc) run as they do; included only where the build has
// oneDNN (CMBRL_HAVE_ONEDNN).
#pragma once

#include <omp.h>

#include <oneapi/dnnl/dnnl.hpp>

namespace cmbrl::onednn {

// Sets the calling thread's OpenMP thread count for its lifetime, then puts the caller's back.
// Every product runs single-threaded under it: oneDNN (OpenMP build) splits a product by the
// caller's count, so a result's bits would otherwise depend on which thread asks.
class ScopedOmpThreads {
 public:
  explicit ScopedOmpThreads(int threads) : before_(omp_get_max_threads()) {
    if (threads != before_) omp_set_num_threads(threads);
  }
  ~ScopedOmpThreads() {
    if (omp_get_max_threads() != before_) omp_set_num_threads(before_);
  }
  ScopedOmpThreads(const ScopedOmpThreads&) = delete;
  ScopedOmpThreads& operator=(const ScopedOmpThreads&) = delete;

 private:
  int before_;
};

}  // namespace cmbrl::onednn

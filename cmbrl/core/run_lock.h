// An exclusive lock on a directory, held while one process works in it: two processes that train
// into the same run directory would interleave their checkpoints. The operating system releases
// it when the process ends, however it ends.
#pragma once

#include <string>

namespace cmbrl {

// Locks `dir`/lock (created if missing). Not thread-safe; movable, not copyable.
class RunLock {
 public:
  // Throws cmbrl::Error naming the directory when another process holds the lock.
  explicit RunLock(const std::string& dir);
  ~RunLock();
  RunLock(RunLock&& other) noexcept;
  RunLock& operator=(RunLock&&) = delete;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace cmbrl

// An exclusive lock on a directory, held while one process works in it: two processes that train
// into the same run directory would interleave their checkpoints. The operating system releases
// it when the process ends, however it ends, so a lock whose holder is gone is seen from the lock
// itself and is never broken by deleting anything.
//
// Two locks are taken, both with flock(2):
//  - on the directory itself, which no one can delete from under a live run while keeping the
//    directory (deleting `dir`/lock does not free the run);
//  - on `dir`/lock, which also records the holder (process, host, since when) for the message a
//    second process gets. On file systems that cannot lock a directory (NFS emulates flock with
//    byte-range locks, which need a file open for writing) the file lock alone guards the run.
#pragma once

#include <string>

namespace cmbrl {

// Locks `dir` and `dir`/lock (created if missing). Not thread-safe; movable, not copyable.
class RunLock {
 public:
  // Throws cmbrl::Error naming the directory (and the holder, where the lock file says) when
  // another process holds it, and when the lock file was replaced or removed while this call
  // took it. Touches nothing in the directory when it refuses.
  explicit RunLock(const std::string& dir);
  ~RunLock();
  RunLock(RunLock&& other) noexcept;
  RunLock& operator=(RunLock&&) = delete;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int dir_fd_ = -1;
  int file_fd_ = -1;
};

}  // namespace cmbrl

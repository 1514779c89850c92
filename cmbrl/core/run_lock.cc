#include "cmbrl/core/run_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "cmbrl/core/check.h"

namespace cmbrl {

RunLock::RunLock(const std::string& dir) {
  const std::string path = dir + "/lock";
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  Require(fd_ >= 0, "cannot open '{}': {}", path, std::strerror(errno));
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    close(fd_);
    fd_ = -1;
    Fail("'{}' is in use by another cmbrl process: wait for it to end (or stop it) first", dir);
  }
}

RunLock::~RunLock() {
  if (fd_ >= 0) close(fd_);  // closing releases the lock
}

RunLock::RunLock(RunLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

}  // namespace cmbrl

#include "cmbrl/core/run_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fmt/format.h>

#include "cmbrl/core/check.h"
#include "cmbrl/core/utc_time.h"

namespace cmbrl {
namespace {

// Who holds a lock, as its lock file says ("" when it says nothing readable).
std::string HolderOf(int fd) {
  char text[256] = {};
  const ssize_t n = pread(fd, text, sizeof(text) - 1, 0);
  if (n <= 0) return "";
  std::string holder(text, static_cast<size_t>(n));
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == '\0')) holder.pop_back();
  return holder.find('\n') == std::string::npos ? holder : "";
}

[[noreturn]] void FailInUse(const std::string& dir, const std::string& holder) {
  Fail("'{}' is in use by another cmbrl process{}: wait for it to end (or stop it) first", dir,
       holder.empty() ? "" : " (" + holder + ")");
}

std::string ThisHolder() {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  return fmt::format("pid {} on {} since {}", getpid(), host, UtcTimestamp());
}

}  // namespace

RunLock::RunLock(const std::string& dir) {
  const std::string path = dir + "/lock";
  try {
    // The directory first: a second process is refused before it creates or opens anything.
    dir_fd_ = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    Require(dir_fd_ >= 0, "cannot open '{}': {}", dir, std::strerror(errno));
    if (flock(dir_fd_, LOCK_EX | LOCK_NB) != 0) {
      if (errno == EWOULDBLOCK) {
        const int holder_fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
        const std::string holder = holder_fd >= 0 ? HolderOf(holder_fd) : "";
        if (holder_fd >= 0) close(holder_fd);
        FailInUse(dir, holder);
      }
      close(dir_fd_);  // a file system that cannot lock directories: the file lock guards alone
      dir_fd_ = -1;
    }
    file_fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    Require(file_fd_ >= 0, "cannot open '{}': {}", path, std::strerror(errno));
    if (flock(file_fd_, LOCK_EX | LOCK_NB) != 0) FailInUse(dir, HolderOf(file_fd_));
    // The file locked must still be the one at `path`: one removed (or replaced) between open and
    // flock would let a process that opens `path` now take a lock of its own beside this one.
    struct stat opened {}, named {};
    Require(fstat(file_fd_, &opened) == 0 && stat(path.c_str(), &named) == 0 &&
                opened.st_dev == named.st_dev && opened.st_ino == named.st_ino,
            "'{}' was removed or replaced while this process locked it: another process is "
            "starting or removing the run in '{}'; try again once it has",
            path, dir);
    // Each call's own errno, read right after it fails (a message's arguments are evaluated in
    // no set order, so errno is never read inside one beside the call that sets it).
    const std::string holder = ThisHolder() + "\n";
    if (ftruncate(file_fd_, 0) != 0) {
      const int cause = errno;
      Fail("could not write '{}': {}", path, std::strerror(cause));
    }
    const ssize_t written = pwrite(file_fd_, holder.data(), holder.size(), 0);
    if (written < 0) {
      const int cause = errno;
      Fail("could not write '{}': {}", path, std::strerror(cause));
    }
    Require(written == static_cast<ssize_t>(holder.size()),
            "could not write '{}': {} of {} bytes written (is the disk full?)", path, written,
            holder.size());
  } catch (...) {
    if (dir_fd_ >= 0) close(dir_fd_);
    if (file_fd_ >= 0) close(file_fd_);
    throw;
  }
}

RunLock::~RunLock() {
  // Closing releases the locks. The holder's line stays: it is read only while the file is
  // locked, and a stale line is overwritten by the next holder.
  if (dir_fd_ >= 0) close(dir_fd_);
  if (file_fd_ >= 0) close(file_fd_);
}

RunLock::RunLock(RunLock&& other) noexcept : dir_fd_(other.dir_fd_), file_fd_(other.file_fd_) {
  other.dir_fd_ = -1;
  other.file_fd_ = -1;
}

}  // namespace cmbrl

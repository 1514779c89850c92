#include "cmbrl/core/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cmbrl/core/check.h"

namespace cmbrl {
namespace {

void WriteAll(const std::filesystem::path& path, std::string_view bytes, int flags) {
  const int fd = open(path.c_str(), flags | O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) FailToWrite(path);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int cause = n < 0 ? errno : ENOSPC;  // a write of nothing: the disk is full
      close(fd);
      errno = cause;
      FailToWrite(path);
    }
    done += static_cast<size_t>(n);
  }
  if (close(fd) != 0) FailToWrite(path);  // NFS and quotas report late, at close
}

}  // namespace

std::ifstream OpenToRead(const std::filesystem::path& path, bool binary) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error && error != std::errc::no_such_file_or_directory) {
    Fail("cannot read '{}': {}", path.string(), error.message());
  }
  Require(std::filesystem::exists(status), "cannot read '{}': it does not exist", path.string());
  Require(!std::filesystem::is_directory(status), "cannot read '{}': it is a folder",
          path.string());
  std::ifstream in(path, binary ? std::ios::in | std::ios::binary : std::ios::in);
  if (!in) {
    const int cause = errno;
    Fail("cannot read '{}': {}", path.string(), std::strerror(cause));
  }
  return in;
}

void FailToWrite(const std::filesystem::path& path) {
  const int cause = errno;  // before the message's arguments, which may call into libc
  Fail("could not write '{}': {}", path.string(), std::strerror(cause));
}

void WriteFile(const std::filesystem::path& path, std::string_view bytes) {
  WriteAll(path, bytes, O_TRUNC);
}

void AppendToFile(const std::filesystem::path& path, std::string_view bytes) {
  WriteAll(path, bytes, O_APPEND);
}

void CloseChecked(std::ofstream& out, const std::filesystem::path& path) {
  // A write that failed earlier left its cause in errno (nothing since has touched the stream).
  int cause = out.fail() ? errno : 0;
  if (!out.fail()) errno = 0;
  out.close();
  if (out.fail()) {
    if (cause == 0) cause = errno != 0 ? errno : EIO;
    errno = cause;
    FailToWrite(path);
  }
}

std::string ReadWholeLines(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) return "";
  std::ifstream in(path, std::ios::binary);
  Require(static_cast<bool>(in), "could not read '{}'", path.string());
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const size_t end = all.rfind('\n');
  return end == std::string::npos ? std::string() : all.substr(0, end + 1);
}

}  // namespace cmbrl

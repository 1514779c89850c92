#include "cmbrl/core/subprocess.h"

#include <fmt/format.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "cmbrl/core/check.h"

extern char** environ;

namespace cmbrl {
namespace {

// Both ends of a pipe, closed when dropped.
struct Pipe {
  std::array<int, 2> ends = {-1, -1};  // read, write
  Pipe() {
    if (pipe(ends.data()) != 0) {
      const int cause = errno;  // read before anything else can change it
      Fail("could not make a pipe: {}", std::strerror(cause));
    }
  }
  ~Pipe() {
    for (const int end : ends) {
      if (end >= 0) close(end);
    }
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
  void CloseWriteEnd() {
    close(ends[1]);
    ends[1] = -1;
  }
};

}  // namespace

std::string CommandLine(const std::string& program, const std::vector<std::string>& args) {
  std::string line = program;
  for (const std::string& arg : args) line += " " + arg;
  return line;
}

ProgramOutput RunProgram(const std::string& program, const std::vector<std::string>& args) {
  Pipe out, err;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out.ends[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err.ends[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, out.ends[0]);
  posix_spawn_file_actions_addclose(&actions, err.ends[0]);
  std::vector<std::string> words = {program};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int failure = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  Require(failure == 0, "could not run '{}': {}{}", CommandLine(program, args),
          std::strerror(failure),
          failure == ENOENT ? fmt::format(" ('{}' is not on PATH)", program) : "");
  out.CloseWriteEnd();
  err.CloseWriteEnd();

  // Read both streams as they come, so that neither fills its pipe and stalls the program.
  ProgramOutput result;
  std::array<pollfd, 2> streams = {pollfd{out.ends[0], POLLIN, 0}, pollfd{err.ends[0], POLLIN, 0}};
  std::array<std::string*, 2> sinks = {&result.output, &result.errors};
  int open_streams = 2;
  std::array<char, 4096> buffer{};
  while (open_streams > 0) {
    if (poll(streams.data(), streams.size(), -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (size_t index = 0; index < streams.size(); ++index) {
      if (streams[index].fd < 0 || streams[index].revents == 0) continue;
      const ssize_t count = read(streams[index].fd, buffer.data(), buffer.size());
      if (count > 0) {
        sinks[index]->append(buffer.data(), static_cast<size_t>(count));
      } else if (count == 0 || errno != EINTR) {
        streams[index].fd = -1;  // ended (poll ignores negative descriptors)
        --open_streams;
      }
    }
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

}  // namespace cmbrl

#include "cmbrl/sweep/sweep_runner.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/parallel.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

// Starts `cmbrl <args>` with its output appended to `log`. The child dies with the sweep (a
// killed sweep leaves no orphan training behind) and runs on its share of the CPUs (`cpus`;
// empty: all), with as many BLAS threads. Everything the child needs is prepared before fork():
// between fork and exec it makes only system calls, as a child of a process with threads
// (OpenBLAS's) must.
pid_t StartTrainer(const std::string& program, const std::vector<std::string>& args,
                   const std::string& log, const std::vector<int>& cpus, int blas_threads) {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  for (const int cpu : cpus) CPU_SET(cpu, &mask);
  std::vector<std::string> environment;
  for (char** entry = environ; *entry != nullptr; ++entry) environment.emplace_back(*entry);
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) {
    environment.push_back("OPENBLAS_NUM_THREADS=" + std::to_string(blas_threads));
  }
  std::vector<char*> envp;
  for (std::string& entry : environment) envp.push_back(entry.data());
  envp.push_back(nullptr);
  std::vector<std::string> words = {program};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);

  const pid_t parent = getpid();
  const pid_t pid = fork();
  Require(pid >= 0, "could not start a training process");
  if (pid > 0) return pid;
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(127);  // the sweep ended before the line above
  if (!cpus.empty()) sched_setaffinity(0, sizeof(mask), &mask);
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd >= 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    close(fd);
  }
  execve(program.c_str(), argv.data(), envp.data());
  _exit(127);
}

}  // namespace

SweepOutcome RunSweep(const SweepGrid& grid, const std::string& sweep_dir, int jobs,
                      const std::string& program,
                      const SweepEventSink& on_event) {
  const PreparedSweep prepared = PrepareSweep(grid, sweep_dir, program, on_event);
  const std::vector<SweepRun>& runs = prepared.runs;
  std::deque<const SweepRun*> queue;
  for (const size_t index : prepared.unfinished) queue.push_back(&runs[index]);
  // Seeds outermost: every cell gets its first seed before any gets its second, so that a sweep
  // stopped part-way (a session's end) has covered the grid evenly.
  const auto seed_rank = [&](const SweepRun* run) {
    return std::find(grid.seeds.begin(), grid.seeds.end(), run->seed) - grid.seeds.begin();
  };
  std::stable_sort(queue.begin(), queue.end(), [&](const SweepRun* a, const SweepRun* b) {
    return seed_rank(a) < seed_rank(b);
  });
  // Each run at a time gets its own CPUs; a finished run's share goes to the next run.
  const std::vector<int> allowed = AllowedCpus();
  const std::vector<std::vector<int>> shares = CpuShares(allowed, jobs);
  std::vector<size_t> free_shares;
  for (size_t share = shares.size(); share-- > 0;) free_shares.push_back(share);
  const int blas_threads = std::max(1, static_cast<int>(allowed.size()) / jobs);
  struct Running {
    const SweepRun* run;
    std::chrono::steady_clock::time_point start;
    std::optional<size_t> share;
  };
  std::map<pid_t, Running> running;
  std::vector<std::string> failed;
  int finished = 0;
  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && static_cast<int>(running.size()) < jobs) {
      const SweepRun& run = *queue.front();
      queue.pop_front();
      const std::vector<std::string> train = TrainArguments(run, grid);
      const std::string log = (fs::path(sweep_dir) / "logs" / (run.name + ".log")).string();
      std::optional<size_t> share;
      if (!free_shares.empty()) {
        share = free_shares.back();
        free_shares.pop_back();
      }
      const std::vector<int> cpus = share ? shares[*share] : std::vector<int>{};
      running[StartTrainer(program, train, log, cpus, blas_threads)] = {
          &run, std::chrono::steady_clock::now(), share};
      on_event({run.name, train[1] == "--resume" ? "resumed" : "started", log, cpus,
                std::nullopt, std::nullopt, "", ""});
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) continue;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const SweepRun& run = *it->second.run;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.start).count();
    if (it->second.share) free_shares.push_back(*it->second.share);
    running.erase(it);
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (ok) {
      ++finished;
    } else {
      failed.push_back(run.name);
    }
    on_event({run.name, ok ? "finished" : "failed", "", {},
              WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), seconds, "", ""});
  }
  SweepOutcome outcome;
  outcome.runs = static_cast<int>(runs.size());
  outcome.finished_now = finished;
  outcome.already_finished = prepared.already_finished;
  outcome.failed = failed;
  return outcome;
}

}  // namespace cmbrl

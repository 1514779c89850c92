// `cmbrl sweep`: the grid of training runs as separate processes, a few at a time, skipping
// finished runs and resuming interrupted ones; also writes the grid as a Slurm job array.
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/arguments.h"
#include "app/commands.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/parallel.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/experiment/sweep.h"
#include "cmbrl/planning/planner_registry.h"

namespace cmbrl::app {
namespace {
namespace fs = std::filesystem;

struct SweepArgs {
  SweepGrid grid;
  std::string out;
  int jobs = 1;
};

std::string ProgramPath() { return fs::read_symlink("/proc/self/exe").string(); }

// Starts `cmbrl <args>` with its output appended to `log`. The child dies with the sweep (a
// killed sweep leaves no orphan training behind) and runs on its share of the CPUs (`cpus`;
// empty: all), with as many BLAS threads. Everything the child needs is prepared before fork():
// between fork and exec it makes only system calls, as a child of a process with threads
// (OpenBLAS's) must.
pid_t Spawn(const std::string& program, const std::vector<std::string>& args,
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

void RunSweep(const SweepArgs& args) {
  const std::vector<SweepRun> runs = PlanSweep(args.grid, args.out);
  RecordOrCheckSweep(args.grid, args.out);
  fs::create_directories(fs::path(args.out) / "logs");
  fs::create_directories(fs::path(args.out) / "runs");
  const std::string program = ProgramPath();
  {
    const fs::path script = fs::path(args.out) / "slurm.sh";
    std::ofstream(script) << SlurmScript(runs, args.grid, args.out, program);
    fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
  }

  std::deque<const SweepRun*> queue;
  int skipped = 0;
  for (const SweepRun& run : runs) {
    if (StatusOf(run) == RunStatus::kFinished) {
      std::cout << nlohmann::ordered_json{{"run", run.name}, {"status", "already finished"}}.dump()
                << std::endl;
      ++skipped;
    } else {
      queue.push_back(&run);
    }
  }
  // Each run at a time gets its own CPUs; a finished run's share goes to the next run.
  const std::vector<int> allowed = AllowedCpus();
  const std::vector<std::vector<int>> shares = CpuShares(allowed, args.jobs);
  std::vector<size_t> free_shares;
  for (size_t share = shares.size(); share-- > 0;) free_shares.push_back(share);
  const int blas_threads = std::max(1, static_cast<int>(allowed.size()) / args.jobs);
  struct Running {
    const SweepRun* run;
    std::chrono::steady_clock::time_point start;
    std::optional<size_t> share;
  };
  std::map<pid_t, Running> running;
  std::vector<std::string> failed;
  int finished = 0;
  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && static_cast<int>(running.size()) < args.jobs) {
      const SweepRun& run = *queue.front();
      queue.pop_front();
      const std::vector<std::string> train = TrainArguments(run, args.grid);
      const std::string log = (fs::path(args.out) / "logs" / (run.name + ".log")).string();
      std::optional<size_t> share;
      if (!free_shares.empty()) {
        share = free_shares.back();
        free_shares.pop_back();
      }
      const std::vector<int> cpus = share ? shares[*share] : std::vector<int>{};
      running[Spawn(program, train, log, cpus, blas_threads)] = {
          &run, std::chrono::steady_clock::now(), share};
      nlohmann::ordered_json line{{"run", run.name},
                                  {"status", train[1] == "--resume" ? "resumed" : "started"},
                                  {"log", log}};
      if (share) line["cpus"] = cpus;
      std::cout << line.dump() << std::endl;
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
    std::cout << nlohmann::ordered_json{
                     {"run", run.name},
                     {"status", ok ? "finished" : "failed"},
                     {"exit", WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)},
                     {"seconds", seconds}}
                     .dump()
              << std::endl;
  }
  std::cout << nlohmann::ordered_json{{"sweep", args.out},
                                      {"runs", runs.size()},
                                      {"finished_now", finished},
                                      {"already_finished", skipped},
                                      {"failed", failed}}
                   .dump()
            << std::endl;
  Require(failed.empty(), "{} run(s) failed: {}; their logs are in {}/logs", failed.size(),
          fmt::join(failed, ", "), args.out);
}

}  // namespace

void AddSweepCommand(CLI::App& parent) {
  auto args = std::make_shared<SweepArgs>();
  args->grid.tasks = EnvNames();
  args->grid.planners = PlannerNames();
  args->grid.seeds = {0, 1, 2};
  CLI::App* command = parent.add_subcommand(
      "sweep",
      "Train a grid of tasks x planners x seeds, N runs at a time, skipping finished runs and "
      "resuming interrupted ones; also writes SWEEP_DIR/slurm.sh for a cluster");
  command->add_option("--tasks", args->grid.tasks, "tasks")->capture_default_str();
  command->add_option("--planners", args->grid.planners, "planners")->capture_default_str();
  command->add_option("--seeds", args->grid.seeds, "seeds")
      ->check(SeedInteger())
      ->capture_default_str();
  command->add_option("--config-dir", args->grid.config_dir,
                      "folder of <task>-<planner>.yaml configs (task in lower case)")
      ->check(CLI::ExistingDirectory)
      ->capture_default_str();
  command->add_option("--steps", args->grid.steps,
                      "agent steps of every run (default: each config's training.total_steps)")
      ->check(IntegerIn(1, kMaxSteps));
  command->add_option("--out", args->out, "sweep directory")->required();
  command->add_option("--jobs", args->jobs, "runs at a time")
      ->check(IntegerIn(1, 1024))
      ->capture_default_str();
  command->callback([args] { RunSweep(*args); });
}

}  // namespace cmbrl::app

// `cmbrl train`: a training run of the paper's Algorithm 2 into a run directory, or the
// continuation of a stopped one.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/arguments.h"
#include "app/commands.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/shell.h"
#include "cmbrl/core/utc_time.h"
#include "cmbrl/train/session_pace.h"
#include "cmbrl/train/trainer.h"

namespace cmbrl::app {
namespace {

struct TrainArgs {
  std::vector<std::string> config;  // composed in order (LoadTrainConfig)
  std::string out;
  std::string resume;
  std::optional<std::int64_t> steps;
  std::optional<std::uint64_t> seed;
  std::vector<std::string> overrides;  // --set
  std::optional<std::string> device;
  double checkpoint_seconds = 300.0;
};

// The signal that asked the run to stop (SIGTERM: Slurm's time limit or preemption, the sweep's
// end; SIGINT: Ctrl-C), or 0.
std::atomic<int> stop_signal{0};

extern "C" void OnStopSignal(int signal) {
  stop_signal.store(signal);
  // write(2) is safe in a handler.
  static const char kMessage[] =
      "\ncmbrl: stopping at a checkpoint after the agent step, fit epoch, rollout round or "
      "value-fit iteration under way; a second signal stops at once\n";
  const ssize_t ignored = write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  (void)ignored;
}

// The first SIGTERM or SIGINT stops the run at a checkpoint taken after the agent step under
// way; a second one kills the process at once (SA_RESETHAND).
void StopAtACheckpointOnSignals() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  for (const int signal : {SIGTERM, SIGINT}) sigaction(signal, &action, nullptr);
}

std::string Duration(double seconds) {
  const int total = static_cast<int>(seconds);
  return total >= 3600 ? fmt::format("{}h{:02}m", total / 3600, total / 60 % 60)
                       : fmt::format("{}m{:02}s", total / 60, total % 60);
}

// The trainer of the run --resume names, after saying on stderr when it goes on on another setup.
std::unique_ptr<Trainer> ResumeRun(const TrainArgs& args) {
  Require(args.config.empty() && args.out.empty() && !args.seed && !args.device &&
              args.overrides.empty(),
          "--resume continues a run with its own config: give no --config, --out, --seed, "
          "--device or --set with it (--steps gives it a new budget)");
  std::unique_ptr<Trainer> trainer = Trainer::Resume(args.resume, args.steps);
  if (!trainer->setup_changes().empty()) {
    std::cerr << fmt::format(
        "cmbrl: warning: '{}' goes on at step {} on another setup than its last session ({}): "
        "from here on its rows are not those an uninterrupted run would have written "
        "(sessions.jsonl)\n",
        args.resume, trainer->steps_done(), fmt::join(trainer->setup_changes(), ", "));
  }
  return trainer;
}

// The trainer of a new run in --out, from --config with --set, --steps, --seed and --device.
std::unique_ptr<Trainer> StartRun(const TrainArgs& args) {
  Require(!args.config.empty() && !args.out.empty(),
          "a new run needs --config FILE and --out RUN_DIR (or --resume RUN_DIR)");
  TrainConfig config = LoadTrainConfig(args.config);
  const std::string source = fmt::format("{}", fmt::join(args.config, "' + '"));
  // Defaults alone are the paper's full PointGoal1 RCE run (hours): only when asked for.
  const bool task_set = std::any_of(args.overrides.begin(), args.overrides.end(),
                                    [](const std::string& o) { return o.rfind("task=", 0) == 0; });
  Require(task_set || ConfigFilesNameKey(args.config, "task") || !config.python.env.empty(),
          "'{}' names no task, so the run would be the defaults' full paper-size PointGoal1 "
          "run: name one (task: PointGoal1 in the file, --set task=PointGoal1, or python.env)",
          source);
  if (!args.overrides.empty()) config = ApplyConfigOverrides(config, args.overrides, "--set");
  if (args.steps) config.training.total_steps = *args.steps;
  if (args.seed) config.seed = *args.seed;
  if (args.device) SetTrainDevice(config, *args.device);
  ValidateTrainConfig(config, source);
  return Trainer::Start(config, args.out);
}

// Returns the signal that stopped the run before its budget was spent, or 0.
int RunTrain(const TrainArgs& args) {
  const std::string run_dir = args.resume.empty() ? args.out : args.resume;
  std::unique_ptr<Trainer> trainer = args.resume.empty() ? StartRun(args) : ResumeRun(args);

  // A live line on the terminal; in a file or a pipe (a sweep's log), one line per unit of work
  // with the time, so that a long run's log says how far it has got.
  const bool live = isatty(STDERR_FILENO) != 0;
  size_t live_width = 0;  // the widest live line so far
  const std::int64_t budget = trainer->learner().budget();
  SessionPace pace(budget, trainer->steps_done());
  const auto session_start = std::chrono::steady_clock::now();
  RunOptions options;
  options.checkpoint_seconds = args.checkpoint_seconds;
  options.stop_requested = [] { return stop_signal.load() != 0; };
  StopAtACheckpointOnSignals();
  options.on_unit = [&](const ProgressSummary& unit) {
    pace.UnitEnded(
        unit.steps,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - session_start).count());
    const double rate = pace.steps_per_second();
    const std::optional<double> left = pace.seconds_left();
    // An MPC unit is one episode; a model-free epoch gives the means over the episodes it ended.
    std::string episodes = "no episode ended";
    if (unit.episodes == 1) {
      episodes =
          fmt::format("EpRet {:.2f} | EpCost {:.0f}", unit.episode_return, unit.episode_cost);
    } else if (unit.episodes > 1) {
      episodes = fmt::format("{} episodes | AverageEpRet {:.2f} | AverageEpCost {:.2f}",
                             unit.episodes, unit.episode_return, unit.episode_cost);
    }
    // A paper-size run takes seconds a step: its pace in seconds a step, not "0.0 steps/s".
    const std::string speed = rate >= 1.0 || rate <= 0.0 ? fmt::format("{:.1f} steps/s", rate)
                                                         : fmt::format("{:.1f} s/step", 1.0 / rate);
    const std::string line = fmt::format(
        "[epoch {}] steps {}/{} | {} | {} | {}", unit.epoch, unit.steps, budget, episodes, speed,
        left ? Duration(*left) + " left" : "time left from the next line");
    if (live) {
      // Spaces over what a longer line before it left on the terminal.
      live_width = std::max(live_width, line.size());
      std::cerr << "\r" << line << std::string(live_width - line.size(), ' ') << std::flush;
    } else {
      std::cerr << UtcTimestamp() << " " << line << std::endl;
    }
  };
  trainer->Run(options);
  if (live) std::cerr << "\n";
  const SessionSummary session = trainer->ThisSession();
  nlohmann::ordered_json split = nlohmann::ordered_json::object();
  for (const auto& [part, seconds] : session.seconds) split[part] = seconds;
  const nlohmann::ordered_json summary = {{"run", run_dir},
                                          {"episodes_this_session", session.episodes},
                                          {"total_env_interacts", trainer->checkpointed_steps()},
                                          {"cost_this_session", session.cost},
                                          {"seconds_this_session", split},
                                          {"cpu_seconds_this_session", session.cpu_seconds}};
  std::cout << summary.dump() << std::endl;
  const int signal = stop_signal.load();
  if (signal != 0 && !trainer->learner().Finished()) {
    std::cerr << fmt::format(
        "cmbrl: {} stopped the run; its last checkpoint is at step {}: `cmbrl train --resume "
        "{}` goes on from there\n",
        signal == SIGTERM ? "SIGTERM" : "SIGINT", trainer->checkpointed_steps(),
        ShellWord(run_dir));
    return signal;
  }
  return 0;
}

}  // namespace

void AddTrainCommand(CLI::App& parent) {
  auto args = std::make_shared<TrainArgs>();
  CLI::App* command = parent.add_subcommand(
      "train",
      "Train an agent (MPC with learned models: RCE, CEM, random, ...; or model-free: TRPO, CPO, "
      "...); resumable; ends with one JSON line of what the session did (episodes, cost, wall "
      "seconds by part, CPU seconds)");
  command
      ->add_option("--config", args->config,
                   "YAML config (see configs/); several are composed in order, later keys over "
                   "earlier ones, e.g. --config configs/pointgoal2-rce.yaml configs/cpu.yaml")
      ->check(ExistingFile());
  command->add_option("--out", args->out, "run directory to create");
  command->add_option("--resume", args->resume, "run directory to continue")
      ->check(ExistingFolder());
  command
      ->add_option("--steps", args->steps,
                   "budget of agent steps (training.total_steps); with --resume, continues the "
                   "run (finished or not) to this budget as if it had been started with it")
      ->check(IntegerIn(1, kMaxSteps));
  command->add_option("--seed", args->seed, "run seed")->check(SeedInteger());
  command->add_option("--device", args->device, "cpu, cuda or cuda:N");
  command->add_option("--set", args->overrides,
                      "SECTION.KEY=VALUE: change the config's keys for this run (written to its "
                      "config.yaml), e.g. --set planning.population=500 classifier.rounds=100");
  command
      ->add_option("--checkpoint-seconds", args->checkpoint_seconds,
                   "a unit of work (an episode, a model fit, a model-free epoch) still going "
                   "this long after the last checkpoint is checkpointed after its agent step, "
                   "fit epoch, rollout round or value-fit iteration under way, so a killed run "
                   "loses at most about this much work (0: after every step); results do not "
                   "depend on it. SIGTERM or Ctrl-C checkpoints at once and stops")
      ->check(NumberIn(0.0, 86400.0))
      ->capture_default_str();
  command->callback([args] {
    const int signal = RunTrain(*args);
    if (signal != 0) throw CLI::RuntimeError(128 + signal);  // as a shell reports a signal
  });
}

}  // namespace cmbrl::app

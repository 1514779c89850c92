// `cmbrl sweep`: the grid of training runs as separate processes, a few at a time, skipping
// finished runs and resuming interrupted ones (the local engine), or as a Slurm job array
// submitted to a cluster and followed there (the Slurm engine).
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "app/arguments.h"
#include "app/commands.h"
#include "cmbrl/core/check.h"
#include "cmbrl/env/registry.h"
#include "cmbrl/planning/planner_registry.h"
#include "cmbrl/sweep/experiment.h"
#include "cmbrl/sweep/slurm_engine.h"
#include "cmbrl/sweep/sweep_runner.h"

namespace cmbrl::app {
namespace {
namespace fs = std::filesystem;

struct SweepArgs {
  SweepGrid grid;
  std::string out;
  int jobs = 1;
  std::string experiment;  // experiments/<name>: its grid, into experiments/<name>/runs
  std::string engine = "local";
  SlurmOptions slurm;
  bool status = false;  // say how far each run has got; start nothing
  std::string train_with;  // the program that trains the runs; empty: this one
};

void PrintEvent(const SweepEvent& event) {
  nlohmann::ordered_json line{{"run", event.run}, {"status", event.status}};
  if (!event.log.empty()) line["log"] = event.log;
  if (!event.cpus.empty()) line["cpus"] = event.cpus;
  if (!event.job.empty()) line["job"] = event.job;
  if (!event.state.empty()) line["state"] = event.state;
  if (event.exit_code) line["exit"] = *event.exit_code;
  if (event.seconds) line["seconds"] = *event.seconds;
  std::cout << line.dump() << std::endl;
}

// `--status`: one line per run (its status, steps reached, budget and training seconds so far,
// when it has begun), then the totals. Reads the runs' folders only: no run is started, no file
// written.
void PrintSweepStatus(const SweepGrid& grid, const std::string& sweep_dir) {
  std::map<std::string, int> counts{{"finished", 0}, {"started", 0}, {"new", 0}};
  std::int64_t steps = 0, budget = 0;
  double seconds = 0.0;
  const std::vector<SweepRun> runs = PlanSweep(grid, sweep_dir);
  for (const SweepRun& run : runs) {
    const RunProgress progress = ProgressOf(run, grid.steps);
    const std::string status = RunStatusName(progress.status);
    ++counts[status];
    steps += std::min(progress.steps, progress.budget);
    budget += progress.budget;
    seconds += progress.seconds.value_or(0.0);
    nlohmann::ordered_json line{{"run", run.name},
                                {"status", status},
                                {"steps", progress.steps},
                                {"budget", progress.budget}};
    if (progress.seconds) line["seconds"] = std::round(*progress.seconds * 10.0) / 10.0;
    if (progress.in_report) line["in_report"] = true;
    std::cout << line.dump() << std::endl;
  }
  std::cout << nlohmann::ordered_json{{"sweep", sweep_dir},
                                      {"runs", runs.size()},
                                      {"finished", counts["finished"]},
                                      {"started", counts["started"]},
                                      {"new", counts["new"]},
                                      {"steps", steps},
                                      {"budget", budget},
                                      {"seconds", std::round(seconds * 10.0) / 10.0}}
                   .dump()
            << std::endl;
}

std::string ProgramPath() { return fs::read_symlink("/proc/self/exe").string(); }

void RunSweepCommand(SweepArgs args, const CLI::App& command) {
  if (!args.experiment.empty()) {
    for (const char* option : {"--tasks", "--planners", "--seeds", "--config-dir", "--steps",
                               "--out"}) {
      Require(command.count(option) == 0,
              "{} is declared by the experiment '{}' ({}): give no {} with an experiment", option,
              args.experiment, kExperimentFile, option);
    }
    const Experiment experiment = LoadExperiment(args.experiment);
    args.grid = ExperimentGrid(experiment);
    args.out = experiment.runs_dir().string();
    std::cout << nlohmann::ordered_json{{"experiment", experiment.name},
                                        {"sha256", experiment.sha256},
                                        {"runs", args.out}}
                     .dump()
              << std::endl;
  }
  Require(!args.out.empty(), "--out SWEEP_DIR is required (or give an experiment folder)");
  if (args.status) {
    for (const char* option :
         {"--jobs", "--engine", "--wait", "--poll", "--sbatch", "--train-with"}) {
      Require(command.count(option) == 0, "{} starts runs; --status starts none: give one of them",
              option);
    }
    PrintSweepStatus(args.grid, args.out);
    return;
  }
  std::string program = ProgramPath();
  if (!args.train_with.empty()) {
    program = fs::absolute(args.train_with).lexically_normal().string();
    Require(access(program.c_str(), X_OK) == 0,
            "--train-with is '{}': expected an executable cmbrl program", args.train_with);
  }
  const bool slurm = args.engine == "slurm";
  if (slurm) {
    if (command.count("--jobs") != 0) args.slurm.max_running = args.jobs;
  } else {
    for (const char* option : {"--wait", "--poll", "--sbatch"}) {
      Require(command.count(option) == 0, "{} is for --engine slurm; the local engine is '{}'",
              option, args.engine);
    }
  }
  const SweepOutcome outcome =
      slurm ? SubmitSweep(args.grid, args.out, program, args.slurm, PrintEvent)
            : RunSweep(args.grid, args.out, args.jobs, program, PrintEvent);
  nlohmann::ordered_json summary{{"sweep", args.out},
                                 {"engine", args.engine},
                                 {"runs", outcome.runs},
                                 {"already_finished", outcome.already_finished}};
  if (slurm) {
    summary["submitted"] = outcome.submitted;
    summary["already_queued"] = outcome.already_queued;
    if (!outcome.job.empty()) summary["job"] = outcome.job;
  }
  if (!slurm || args.slurm.wait) {
    summary["finished_now"] = outcome.finished_now;
    summary["failed"] = outcome.failed;
  }
  std::cout << summary.dump() << std::endl;
  Require(outcome.failed.empty(),
          "{} run(s) did not finish: {}; their logs are in {}/logs{}", outcome.failed.size(),
          fmt::join(outcome.failed, ", "), args.out,
          slurm ? "; run the same sweep again to resume them" : "");
}

}  // namespace

void AddSweepCommand(CLI::App& parent) {
  auto args = std::make_shared<SweepArgs>();
  args->grid.tasks = PaperEnvNames();
  args->grid.planners = PaperPlannerNames();
  args->grid.seeds = {0, 1, 2};
  CLI::App* command = parent.add_subcommand(
      "sweep",
      "Train a grid of tasks x planners x seeds (or an experiment's, from its experiment.yaml), "
      "N runs at a time, skipping finished runs and resuming interrupted ones; also writes "
      "SWEEP_DIR/slurm.sh for a cluster");
  command
      ->add_option("experiment", args->experiment,
                   "experiment folder (experiments/<name>, holding experiment.yaml): runs its "
                   "grid into experiments/<name>/runs, or resumes it")
      ->check(ExistingFolder());
  command->add_option("--tasks", args->grid.tasks, "tasks")->capture_default_str();
  command->add_option("--planners,--methods", args->grid.planners,
                      fmt::format("planners ({}; without this option the paper's: {}) and/or "
                                  "model-free algorithms (trpo, trpo-lagrangian, cpo, ppo, "
                                  "ppo-lagrangian)",
                                  fmt::join(PlannerNames(), ", "),
                                  fmt::join(PaperPlannerNames(), ", ")))
      ->capture_default_str();
  command->add_option("--seeds", args->grid.seeds, "seeds")
      ->check(SeedInteger())
      ->capture_default_str();
  command->add_option("--config-dir", args->grid.config_dir,
                      "folder of <task>-<planner>.yaml configs (task in lower case)")
      ->check(ExistingFolder())
      ->capture_default_str();
  command->add_option("--steps", args->grid.steps,
                      "agent steps of every run (default: each config's training.total_steps)")
      ->check(IntegerIn(1, kMaxSteps));
  command->add_option("--out", args->out, "sweep directory (without an experiment)");
  command->add_option("--jobs", args->jobs,
                      "runs at a time (slurm: the array's limit of tasks at a time, none unless "
                      "given)")
      ->check(IntegerIn(1, 1024))
      ->capture_default_str();
  command
      ->add_option("--engine", args->engine,
                   "local: train here, --jobs runs at a time; slurm: submit the unfinished runs "
                   "as one job array (SWEEP_DIR/slurm.sh) with sbatch")
      ->check(CLI::IsMember({"local", "slurm"}))
      ->capture_default_str();
  command
      ->add_option("--train-with", args->train_with,
                   "the cmbrl program that trains the runs (default: this one), so that a newer "
                   "build can carry on an experiment whose runs an older one makes (one binary "
                   "per experiment)")
      ->check(ExistingFile());
  command->add_flag("--status", args->status,
                    "start nothing: print each run's status (new, started, finished), the steps "
                    "it has reached and its budget, one JSON line each, then the totals");
  command->add_flag("--wait", args->slurm.wait,
                    "slurm: follow the array with squeue until every task has left the queue, "
                    "then say which runs finished");
  command->add_option("--poll", args->slurm.poll_seconds, "slurm: seconds between squeue queries")
      ->check(NumberIn(0.1, 3600.0))
      ->capture_default_str();
  command
      ->add_option("--sbatch", args->slurm.sbatch_args,
                   "slurm: an sbatch option for the array, e.g. --sbatch=--partition=cpu "
                   "(repeat it for several); it overrides slurm.sh's own")
      ->allow_extra_args(false);
  command->callback([args, command] { RunSweepCommand(*args, *command); });
}

}  // namespace cmbrl::app

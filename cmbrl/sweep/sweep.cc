#include "cmbrl/sweep/sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "cmbrl/config/config.h"
#include "cmbrl/core/check.h"
#include "cmbrl/core/closest_name.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/shell.h"
#include "cmbrl/env/task_list.h"
#include "cmbrl/report/run_logs.h"
#include "cmbrl/run/run_directory.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Throws cmbrl::Error naming an unknown or repeated task, method or seed, a bad --steps or a
// missing overlay: a repeated one would name one run twice, and two processes would train it.
void CheckGrid(const SweepGrid& grid) {
  Require(!grid.tasks.empty() && !grid.planners.empty() && !grid.seeds.empty(),
          "a sweep needs at least one task, one planner and one seed");
  // A built-in task, or one of the caller's own (a task file's, a Python environment's) whose
  // presets <task>-<method>.yaml are in the config folder.
  const std::vector<std::string>& known_tasks = EnvNames();
  for (const std::string& task : grid.tasks) {
    if (std::find(known_tasks.begin(), known_tasks.end(), task) != known_tasks.end()) continue;
    const bool named = !task.empty() && std::isalpha(static_cast<unsigned char>(task[0])) &&
                       std::all_of(task.begin(), task.end(), [](char c) {
                         return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                       });
    const fs::path preset =
        fs::path(grid.config_dir) / (Lower(task) + "-" + grid.planners.front() + ".yaml");
    Require(named && fs::exists(preset),
            "unknown task '{}'{}: expected some of {}, or a task of its own (letters, digits "
            "and _) with its presets <task>-<method>.yaml in '{}'",
            task, DidYouMean(task, known_tasks), fmt::join(known_tasks, ", "), grid.config_dir);
  }
  // Methods: the MPC planners and the model-free algorithms (configs <task>-<method>.yaml).
  const std::vector<std::string> known_methods = MethodNames();
  for (const std::string& method : grid.planners) {
    Require(std::find(known_methods.begin(), known_methods.end(), method) != known_methods.end(),
            "unknown planner or algorithm '{}'{}: expected some of {}", method,
            DidYouMean(method, known_methods), fmt::join(known_methods, ", "));
  }
  Require(std::set<std::string>(grid.tasks.begin(), grid.tasks.end()).size() == grid.tasks.size(),
          "tasks {} repeat a task: each run of the grid needs its own", fmt::join(grid.tasks, " "));
  Require(std::set<std::string>(grid.planners.begin(), grid.planners.end()).size() ==
              grid.planners.size(),
          "methods {} repeat a method: each run of the grid needs its own",
          fmt::join(grid.planners, " "));
  Require(std::set<std::uint64_t>(grid.seeds.begin(), grid.seeds.end()).size() ==
              grid.seeds.size(),
          "seeds {} repeat a seed: each run needs its own", fmt::join(grid.seeds, " "));
  Require(!grid.steps || *grid.steps >= 1, "--steps is {}: expected a positive number",
          grid.steps.value_or(0));
  for (const std::string& overlay : grid.overlays) {
    Require(fs::is_regular_file(overlay), "no config '{}': expected a YAML file to compose over "
            "each run's preset", overlay);
  }
}

// A setting of the axes: its name ("population=500", several joined by '-'; SweepRunName) and
// its overrides.
using AxisPoint = std::pair<std::string, std::vector<std::string>>;

// Every combination of the axes' values, in the axes' order; one empty point for no axes.
std::vector<AxisPoint> AxisPoints(const std::vector<SweepAxis>& axes) {
  std::vector<AxisPoint> points = {{"", {}}};
  for (const SweepAxis& axis : axes) {
    Require(!axis.values.empty(), "axis '{}' has no values: expected a list of at least one",
            axis.key);
    Require(std::set<std::string>(axis.values.begin(), axis.values.end()).size() ==
                axis.values.size(),
            "axis '{}' repeats a value in {}: each value makes its own runs", axis.key,
            fmt::join(axis.values, ", "));
    std::vector<AxisPoint> longer;
    for (const auto& [name, overrides] : points) {
      for (const std::string& value : axis.values) {
        std::vector<std::string> with = overrides;
        with.push_back(axis.key + "=" + value);
        longer.emplace_back((name.empty() ? "" : name + "-") + SettingWord(axis.key, value), with);
      }
    }
    points = longer;
  }
  return points;
}

}  // namespace

std::vector<SweepRun> PlanSweep(const SweepGrid& grid, const std::string& sweep_dir) {
  CheckGrid(grid);
  const std::vector<AxisPoint> points = AxisPoints(grid.axes);
  std::vector<SweepRun> runs;
  for (const std::string& task : grid.tasks) {
    for (const std::string& planner : grid.planners) {
      const std::string stem = Lower(task) + "-" + planner;
      const fs::path config = fs::path(grid.config_dir) / (stem + ".yaml");
      Require(fs::exists(config), "no config '{}' for {} with {}: expected <task>-<planner>.yaml "
              "in --config-dir",
              config.string(), task, planner);
      // A run is what its name says: its preset (with the overlays) trains that task and method.
      std::vector<std::string> composed = {config.string()};
      composed.insert(composed.end(), grid.overlays.begin(), grid.overlays.end());
      const TrainConfig preset = LoadTrainConfig(composed);
      Require(preset.task == task && MethodOf(preset) == planner,
              "'{}' trains task '{}' with '{}', not '{}' with '{}' as its name says: give the "
              "preset 'task: {}' and its method",
              fmt::format("{}", fmt::join(composed, "' + '")), preset.task, MethodOf(preset), task,
              planner, task);
      for (const auto& [setting, point_overrides] : points) {
        for (const std::uint64_t seed : grid.seeds) {
          SweepRun run;
          run.name = SweepRunName(task, planner, setting, seed);
          run.task = task;
          run.planner = planner;
          run.seed = seed;
          run.config_paths = {config.string()};
          run.config_paths.insert(run.config_paths.end(), grid.overlays.begin(),
                                  grid.overlays.end());
          run.overrides = grid.overrides;
          run.overrides.insert(run.overrides.end(), point_overrides.begin(),
                               point_overrides.end());
          run.run_dir = (fs::path(sweep_dir) / "runs" / run.name).string();
          if (!grid.reported_dir.empty()) {
            run.reported_run_dir = (fs::path(grid.reported_dir) / run.name).string();
          }
          runs.push_back(run);
        }
      }
    }
  }
  return runs;
}

namespace {

// The folder that holds a run's config and progress: its run_dir, else its report's logs, else
// none (a new run). `in_report` says which.
std::optional<RunDirectory> HeldRun(const SweepRun& run, bool& in_report) {
  in_report = false;
  if (RunDirectory dir(run.run_dir); dir.HoldsRun()) return dir;
  if (run.reported_run_dir.empty()) return std::nullopt;
  if (RunDirectory logs(run.reported_run_dir); logs.HoldsRun()) {
    in_report = true;
    return logs;
  }
  return std::nullopt;
}

}  // namespace

RunProgress ProgressOf(const SweepRun& run, std::optional<std::int64_t> budget) {
  RunProgress progress;
  const std::optional<RunDirectory> dir = HeldRun(run, progress.in_report);
  if (!dir) {
    progress.budget =
        budget.value_or(ApplyConfigOverrides(LoadTrainConfig(run.config_paths), run.overrides,
                                             "the overrides of sweep run '" + run.name + "'")
                            .training.total_steps);
    return progress;
  }
  const TrainConfig config = LoadTrainConfig(dir->config_file().string());
  progress.budget = budget.value_or(config.training.total_steps);
  progress.status = progress.in_report ? RunStatus::kNew : RunStatus::kStarted;
  std::vector<EpisodePoint> episodes;
  try {
    episodes = EpisodeReaderOf(FamilyOf(config.algorithm).log)(
        dir->progress_file().string(), std::nullopt);
  } catch (const Error&) {
    // A process killed while writing a row leaves it half written; resuming repairs that.
    if (progress.in_report) throw;  // a report's log is written whole: damaged, not cut short
    return progress;
  }
  if (!episodes.empty()) progress.steps = episodes.back().end_step;
  if (!episodes.empty() && std::isfinite(episodes.back().elapsed_seconds)) {
    progress.seconds = episodes.back().elapsed_seconds;
  }
  if (!episodes.empty() && progress.steps >= progress.budget) {
    progress.status = RunStatus::kFinished;
  }
  if (!progress.in_report) {
    // A checkpoint in the middle of an episode (hours long at the paper's sizes) is ahead of
    // the rows. Its manifest alone is read; a damaged one is for the resume to name.
    // A run with a checkpoint folder is finished only when that checkpoint holds it: rows
    // beside a deleted manifest or a damaged checkpoint go to the resume, which names what is
    // wrong, instead of passing as finished.
    bool held = !fs::exists(dir->checkpoint_dir());
    try {
      const std::optional<CheckpointManifest> checkpoint =
          VerifiedCheckpoint(*dir, /*files=*/false);
      held = held || checkpoint.has_value();
      if (checkpoint && checkpoint->steps_done && *checkpoint->steps_done > progress.steps) {
        progress.steps = *checkpoint->steps_done;
      }
      if (checkpoint && checkpoint->elapsed_seconds > progress.seconds.value_or(0.0)) {
        progress.seconds = checkpoint->elapsed_seconds;
      }
    } catch (const Error&) {
    }
    if (!held && progress.status == RunStatus::kFinished) progress.status = RunStatus::kStarted;
  }
  return progress;
}

RunStatus StatusOf(const SweepRun& run, std::optional<std::int64_t> budget) {
  // A new run's budget would compose its configs: not needed to know that it is new.
  bool in_report = false;
  if (!HeldRun(run, in_report)) return RunStatus::kNew;
  return ProgressOf(run, budget).status;
}

const char* RunStatusName(RunStatus status) {
  switch (status) {
    case RunStatus::kNew:
      return "new";
    case RunStatus::kStarted:
      return "started";
    case RunStatus::kFinished:
      return "finished";
  }
  Fail("unknown run status");
}

void RecordOrCheckSweep(const SweepGrid& grid, const std::string& sweep_dir) {
  const fs::path path = fs::path(sweep_dir) / "sweep.json";
  nlohmann::json axes = nlohmann::json::array();
  for (const SweepAxis& axis : grid.axes) axes.push_back({{"key", axis.key}, {"values", axis.values}});
  nlohmann::json overlays = nlohmann::json::array();
  for (const std::string& overlay : grid.overlays) {
    overlays.push_back(fs::absolute(overlay).lexically_normal().string());
  }
  const nlohmann::json settings = {
      {"config_dir", fs::absolute(grid.config_dir).lexically_normal().string()},
      {"steps", grid.steps ? nlohmann::json(*grid.steps) : nlohmann::json(nullptr)},
      {"overlays", overlays},
      {"overrides", grid.overrides},
      {"axes", axes}};
  if (fs::exists(path)) {
    std::ifstream in(path);
    nlohmann::json recorded;
    try {
      recorded = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& error) {
      Fail("'{}' is not valid JSON: {}", path.string(), error.what());
    }
    const nlohmann::json recorded_steps = recorded.value("steps", nlohmann::json());
    // A larger budget continues the sweep's runs (train --resume --steps); nothing else may
    // change.
    const nlohmann::json& steps = settings["steps"];
    const bool longer = recorded_steps.is_number_integer() && steps.is_number_integer() &&
                        steps.get<std::int64_t>() > recorded_steps.get<std::int64_t>();
    for (const char* key : {"config_dir", "steps", "overlays", "overrides", "axes"}) {
      if (longer && std::string(key) == "steps") continue;
      // A sweep recorded before overlays, overrides and axes existed had none of them.
      const nlohmann::json none = std::string(key) == "config_dir" || std::string(key) == "steps"
                                      ? nlohmann::json()
                                      : nlohmann::json::array();
      Require(recorded.value(key, none) == settings[key],
              "this sweep was started with {} {}, now {} is {}: finish it with the same "
              "settings (or a larger --steps), or use another --out",
              key, recorded.value(key, none).dump(), key, settings[key].dump());
    }
    if (!longer) return;
  }
  fs::create_directories(sweep_dir);
  const fs::path tmp = path.string() + ".tmp";
  WriteFile(tmp, settings.dump(2) + "\n");
  fs::rename(tmp, path);
}

std::vector<std::string> TrainArguments(const SweepRun& run, const SweepGrid& grid) {
  std::vector<std::string> args = {"train", "--resume", run.run_dir};
  if (StatusOf(run) == RunStatus::kNew) args = NewRunArguments(run);
  if (grid.steps) {
    args.push_back("--steps");
    args.push_back(std::to_string(*grid.steps));
  }
  return args;
}

std::vector<std::string> NewRunArguments(const SweepRun& run) {
  std::vector<std::string> args = {"train", "--config"};
  args.insert(args.end(), run.config_paths.begin(), run.config_paths.end());
  if (!run.overrides.empty()) {
    args.push_back("--set");
    args.insert(args.end(), run.overrides.begin(), run.overrides.end());
  }
  for (const std::string& word : {std::string("--seed"), std::to_string(run.seed),
                                  std::string("--out"), run.run_dir}) {
    args.push_back(word);
  }
  return args;
}

std::vector<std::vector<int>> CpuShares(const std::vector<int>& cpus, int jobs) {
  Require(jobs >= 1, "jobs is {}: expected at least 1", jobs);
  const size_t per_job = cpus.size() / static_cast<size_t>(jobs);
  if (per_job == 0) return {};
  std::vector<std::vector<int>> shares;
  for (size_t job = 0; job < static_cast<size_t>(jobs); ++job) {
    shares.emplace_back(cpus.begin() + static_cast<std::ptrdiff_t>(job * per_job),
                        cpus.begin() + static_cast<std::ptrdiff_t>((job + 1) * per_job));
  }
  return shares;
}

PreparedSweep PrepareSweep(const SweepGrid& grid, const std::string& sweep_dir,
                           const std::string& program, const SweepEventSink& on_event) {
  PreparedSweep prepared;
  prepared.runs = PlanSweep(grid, sweep_dir);
  fs::create_directories(sweep_dir);
  prepared.lock = std::make_unique<RunLock>(sweep_dir);
  RecordOrCheckSweep(grid, sweep_dir);
  fs::create_directories(fs::path(sweep_dir) / "logs");
  fs::create_directories(fs::path(sweep_dir) / "runs");
  const fs::path script = fs::path(sweep_dir) / "slurm.sh";
  WriteFile(script, SlurmScript(prepared.runs, grid, sweep_dir, program));
  fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
  for (size_t index = 0; index < prepared.runs.size(); ++index) {
    const SweepRun& run = prepared.runs[index];
    // A run in neither folder is new: its budget (composed from its configs) is not needed.
    bool in_report = false;
    const RunProgress progress =
        HeldRun(run, in_report) ? ProgressOf(run, grid.steps) : RunProgress{};
    Require(!progress.in_report || progress.status == RunStatus::kFinished,
            "run '{}' is in the report's logs ({}) at step {} of {}, and not in {}: its "
            "checkpoints stayed where it ran. Take it up there, or remove its logs from the "
            "report to run it again from the start here",
            run.name, run.reported_run_dir, progress.steps, progress.budget, run.run_dir);
    if (progress.status == RunStatus::kFinished) {
      on_event({run.name,
                progress.in_report ? "already finished (in the report)" : "already finished",
                "",
                {},
                std::nullopt,
                std::nullopt,
                "",
                ""});
      ++prepared.already_finished;
    } else {
      prepared.unfinished.push_back(index);
    }
  }
  return prepared;
}

// A value of an #SBATCH line: as it is, or in double quotes (which sbatch's directive parser
// removes) where it holds a space or another character a shell would split on. Throws
// cmbrl::Error for a double quote or a line break, which no #SBATCH line can carry.
static std::string SbatchWord(const std::string& value) {
  Require(value.find_first_of("\"\n\r") == std::string::npos,
          "'{}': a Slurm sweep's folder cannot hold a double quote or a line break (#SBATCH "
          "--output cannot name it): choose another --out",
          value);
  return ShellWord(value) == value ? value : "\"" + value + "\"";
}

std::string SlurmScript(const std::vector<SweepRun>& runs, const SweepGrid& grid,
                        const std::string& sweep_dir, const std::string& program) {
  const std::string dir = fs::absolute(sweep_dir).lexically_normal().string();
  std::string script = fmt::format(
      "#!/bin/bash\n"
      "# The sweep's grid as a Slurm job array, one task per run: sbatch {0}/slurm.sh\n"
      "# Each task resumes its run if it has started, so a requeued task, or a resubmitted sweep,\n"
      "# finishes what was interrupted. Written by `cmbrl sweep` (which submits it with\n"
      "# --engine slurm); give partitions and limits as sbatch options, or edit them here.\n"
      "#SBATCH --job-name=cmbrl-sweep\n"
      "#SBATCH --array=0-{1}\n"
      "#SBATCH --cpus-per-task=2\n"
      "#SBATCH --output={4}\n"
      "#SBATCH --open-mode=append\n"
      "#SBATCH --requeue\n"
      "#SBATCH --signal=B:USR1@{3}\n"
      "set -euo pipefail\n"
      "# As many BLAS threads as the task has CPUs, unless the caller chose.\n"
      "export OPENBLAS_NUM_THREADS=\"${{OPENBLAS_NUM_THREADS:-${{SLURM_CPUS_PER_TASK:-1}}}}\"\n"
      "cmbrl={2}\n"
      "case \"$SLURM_ARRAY_TASK_ID\" in\n",
      dir, runs.size() - 1, ShellQuote(program), kSlurmTimeLimitLeadSeconds,
      SbatchWord(dir + "/logs/slurm-%a.log"));
  const std::string steps = grid.steps ? fmt::format(" --steps {}", *grid.steps) : "";
  for (size_t index = 0; index < runs.size(); ++index) {
    SweepRun run = runs[index];
    run.run_dir = fs::absolute(run.run_dir).string();
    for (std::string& path : run.config_paths) path = fs::absolute(path).string();
    std::vector<std::string> words;
    for (const std::string& word : NewRunArguments(run)) words.push_back(ShellQuote(word));
    script += fmt::format("  {}) run_dir={}; start=({});;\n", index, ShellQuote(run.run_dir),
                          fmt::join(words, " "));
  }
  script += "esac\n";
  // A run exists once its config file does (RunDirectory::HoldsRun).
  script += fmt::format("if [ -f \"$run_dir/{}\" ]; then\n",
                        RunDirectory("").config_file().filename().string());
  script += "  command=(\"$cmbrl\" train --resume \"$run_dir\"" + steps + ")\n";
  script += "else\n";
  script += "  command=(\"$cmbrl\" \"${start[@]}\"" + steps + ")\n";
  script += "fi\n";
  // The run is a child, not exec'd, so that the script can requeue the task after it; the
  // script must then outlive it, or Slurm would end the task with the script.
  script += fmt::format(
      R"(# {0} s before the task's time limit Slurm sends USR1 to this script alone (--signal
# above; another lead: --sbatch=--signal=B:USR1@SECONDS). The script then asks the run to stop
# (SIGTERM: it checkpoints after the agent step, fit epoch, rollout round or value-fit iteration
# under way), waits for it, and requeues the task, which resumes the run. The run is started deaf to USR1, so
# that it hears of the limit once. A cancellation or a preemption sends SIGTERM to the run
# itself: the script, which ignores it, waits until the run has checkpointed and stopped.
trap '' USR1
"${{command[@]}}" &
pid=$!
near_limit=0
trap 'if [ "$near_limit" = 0 ]; then near_limit=1; kill -TERM "$pid" 2> /dev/null || true; fi' USR1
trap ':' TERM
# A trapped signal ends `wait` early: wait until the run is gone, then take its status.
while kill -0 "$pid" 2> /dev/null; do wait "$pid" || true; done
status=0
wait "$pid" || status=$?
if [ "$near_limit" = 1 ]; then
  echo "cmbrl sweep: Slurm says the time limit is near; the run stopped at a checkpoint" \
    "(exit $status) and task $SLURM_ARRAY_TASK_ID requeues itself to go on"
  scontrol requeue "$SLURM_JOB_ID" ||
    echo "cmbrl sweep: the task could not requeue itself: run the same sweep again to go on"
fi
exit "$status"
)",
      kSlurmTimeLimitLeadSeconds);
  return script;
}

}  // namespace cmbrl

// A grid of training runs (tasks x planners x seeds) in one sweep directory, for the paper's
// Table I and learning curves (Section V). The grid is plain data: which runs exist, where their
// configs and directories are, whether they finished, and the job-array script that runs the same
// grid on a Slurm cluster. Starting processes is the program's business (`cmbrl sweep`).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/run_lock.h"

namespace cmbrl {

// An axis of overrides: one config key (section.key, as `--set` takes it) and its values, each
// written as YAML ("0.3", "[256, 256]"). A grid with axes has a run for every combination.
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
};

struct SweepGrid {
  std::vector<std::string> tasks;     // PointGoal1 ...
  std::vector<std::string> planners;  // methods: rce, cem, random, trpo-lagrangian ...
  std::vector<std::uint64_t> seeds;
  std::string config_dir = "configs";      // holds <task>-<planner>.yaml, task in lower case
  std::optional<std::int64_t> steps;       // overrides training.total_steps of every run
  // Config files composed over each <task>-<planner>.yaml, in order (a preset family such as
  // configs/cpu.yaml), then `overrides` ("section.key=value") of every run, then the axes.
  std::vector<std::string> overlays;
  std::vector<std::string> overrides;
  std::vector<SweepAxis> axes;
  // A report's run-logs/ folder (an experiment's report/run-logs), or empty: a run that is not
  // in the sweep's runs/ but finished there is not run again, so that a sweep taken up on a new
  // machine makes only the runs its committed report lacks.
  std::string reported_dir;
};

struct SweepRun {
  std::string name;  // pointgoal1-rce-s0; with axes pointgoal1-rce-threshold=0.3-s0
  std::string task, planner;
  std::uint64_t seed = 0;
  // config_dir/pointgoal1-rce.yaml, then the grid's overlays: composed in this order.
  std::vector<std::string> config_paths;
  std::vector<std::string> overrides;  // the grid's, then this run's axis values
  std::string run_dir;                 // sweep_dir/runs/pointgoal1-rce-s0
  std::string reported_run_dir;        // the grid's reported_dir/pointgoal1-rce-s0, or empty
};

// Every run of the grid, tasks outermost, then planners, then the axes' combinations (the first
// axis outermost), then seeds. Throws cmbrl::Error naming an unknown task or planner, an empty
// list, a repeated seed, a missing config file, or an axis without values or with a repeated
// value.
std::vector<SweepRun> PlanSweep(const SweepGrid& grid, const std::string& sweep_dir);

// Where a run stands: not started, started (resume it), or finished (its progress reached
// `budget`, or the run's own budget without one). A run absent from its run_dir is judged by its
// reported_run_dir when that holds one: finished there, it is finished.
enum class RunStatus { kNew, kStarted, kFinished };
RunStatus StatusOf(const SweepRun& run, std::optional<std::int64_t> budget = std::nullopt);

// "new", "started" or "finished".
const char* RunStatusName(RunStatus status);

// How far a run has got: its status, the steps its progress log or its last checkpoint (which
// may be taken in the middle of an episode) has reached (agent steps, or environment steps for a
// model-free run; 0 before either, or while a row half written by a killed process is there,
// which resuming repairs) and the steps it runs to
// (`budget`, else its own training.total_steps: from its config.yaml once started, else from
// its configs and overrides as the sweep would compose them). Reads only; throws cmbrl::Error
// naming a config that does not load.
struct RunProgress {
  RunStatus status = RunStatus::kNew;
  std::int64_t steps = 0;
  std::int64_t budget = 0;
  // Its training time so far over all its sessions, as far as `steps` (the later of its last
  // row's Time and its checkpoint's); absent before either, or when its log keeps no Time.
  std::optional<double> seconds;
  // Read from the report's logs (reported_run_dir), the run being absent from run_dir. Such a
  // run short of its budget is kNew: its checkpoints stayed on the machine that made it.
  bool in_report = false;
};
RunProgress ProgressOf(const SweepRun& run, std::optional<std::int64_t> budget = std::nullopt);

// Records the grid in sweep_dir/sweep.json, or checks it against the recorded one, so that a
// restarted sweep cannot silently mix budgets or config folders. A larger --steps than recorded
// is allowed and recorded: the sweep then continues every run to it. Throws cmbrl::Error naming
// the setting that differs otherwise.
void RecordOrCheckSweep(const SweepGrid& grid, const std::string& sweep_dir);

// The command line of one run: `train --resume DIR` when it has started (with `--steps N` when
// the grid sets a budget: a run made with a smaller one continues to it), else a new run.
std::vector<std::string> TrainArguments(const SweepRun& run, const SweepGrid& grid);

// The command line that starts a new run: its configs composed, its overrides, seed and folder.
std::vector<std::string> NewRunArguments(const SweepRun& run);

// The CPUs of each of `jobs` runs at a time: `cpus` split into `jobs` equal contiguous shares
// (a remainder stays unused), so that each run's threads (BLAS, OpenMP, the classifier's) see
// only its own cores. Empty when there are fewer CPUs than jobs: the runs then share them all.
std::vector<std::vector<int>> CpuShares(const std::vector<int>& cpus, int jobs);

// What happened to one run, as a sweep goes (on this machine or on Slurm).
struct SweepEvent {
  std::string run;                // its name
  // "already finished", "started", "resumed", "already queued", "submitted", "running",
  // "requeued", "finished", "failed"
  std::string status;
  std::string log;                // its log file (started, resumed, submitted)
  std::vector<int> cpus;          // its CPUs (started, resumed; empty: it shares them all)
  std::optional<int> exit_code;   // finished, failed on this machine (128 + signal when killed)
  std::optional<double> seconds;  // finished, failed on this machine: wall time of this session
  std::string job;                // Slurm: its array task ("1234_5")
  std::string state;              // Slurm: the task's last state (COMPLETED, CANCELLED, ...)
};

struct SweepOutcome {
  int runs = 0;
  int finished_now = 0;
  int already_finished = 0;
  int submitted = 0;       // Slurm: array tasks submitted
  int already_queued = 0;  // Slurm: runs whose task of an earlier submission is still queued
  std::string job;    // Slurm: the array job's id, when one was submitted
  std::vector<std::string> failed;
};

using SweepEventSink = std::function<void(const SweepEvent&)>;

// A sweep directory made ready for an engine: its runs, and which of them are left to do. The
// directory is locked against a second sweep while this lives (sweep_dir/lock): two sweeps of
// one folder would each take the other's runs for failed ones.
struct PreparedSweep {
  std::vector<SweepRun> runs;
  std::vector<size_t> unfinished;  // indices into runs, in grid order
  int already_finished = 0;
  std::unique_ptr<RunLock> lock;
};

// Makes sweep_dir ready for either engine: plans the grid, records it (or checks it against the
// recorded one), makes logs/ and runs/, writes slurm.sh for `program`, and reports each finished
// run to `on_event` as "already finished" ("already finished (in the report)" for one finished in
// the grid's reported_dir). Throws cmbrl::Error as PlanSweep and RecordOrCheckSweep do, and
// naming a run that the report holds unfinished while runs/ lacks it (its checkpoints are
// elsewhere), or another process that holds sweep_dir (a second sweep of it).
PreparedSweep PrepareSweep(const SweepGrid& grid, const std::string& sweep_dir,
                           const std::string& program, const SweepEventSink& on_event);

// How long before a task's time limit Slurm warns its slurm.sh, which then stops the run at a
// checkpoint and requeues the task: longer than a paper-size agent step, fit epoch or model-free
// epoch on one core (about 10 s, 30 s and 1-3 minutes).
inline constexpr int kSlurmTimeLimitLeadSeconds = 300;

// sweep_dir/slurm.sh: a job array with one task per run, each resuming or starting its run with
// `program` (an absolute path), logs in sweep_dir/logs (appended to, so that a requeued task's
// log keeps its first part). Tasks are requeueable: one stopped by a node failure or preemption
// (or `scontrol requeue`) starts again and resumes its run from its checkpoint, and one that
// nears its time limit stops its run at a checkpoint and requeues itself.
std::string SlurmScript(const std::vector<SweepRun>& runs, const SweepGrid& grid,
                        const std::string& sweep_dir, const std::string& program);

}  // namespace cmbrl

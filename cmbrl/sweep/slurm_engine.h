// The Slurm engine: a sweep's grid submitted to a cluster as one job array (SWEEP_DIR/slurm.sh,
// one task per unfinished run), and, when asked, followed until every task has left the queue.
// A task that is requeued resumes its run from its checkpoint; one that is killed (cancelled, out
// of time) leaves its run started, and submitting the sweep again resumes it.
#pragma once

#include <string>
#include <vector>

#include "cmbrl/sweep/sweep.h"

namespace cmbrl {

struct SlurmOptions {
  std::vector<std::string> sbatch_args;  // more sbatch options ("--partition=cpu"), after ours
  int max_running = 0;                   // tasks of the array at a time (--array=...%N); 0: any
  bool wait = false;                     // follow the array until every task has left the queue
  double poll_seconds = 30;              // seconds between two squeue queries while following
};

// Submits every run of the grid that has not finished as a task of one job array with `sbatch`
// (found on PATH), recording the job in sweep_dir/slurm-jobs.jsonl, and reports each as
// "submitted" (or "already finished"). A run whose task of an earlier submission is still in the
// queue is not submitted again but followed ("already queued"). With options.wait, polls `squeue`
// until every task has left the queue, reports a task "running" when it starts and "requeued" when
// it is back in the queue after running, and each run "finished" when its progress reached the
// budget, else "failed" with the task's last Slurm state. Throws cmbrl::Error naming the command
// and what it printed when sbatch fails or squeue keeps failing, and as PrepareSweep does.
SweepOutcome SubmitSweep(const SweepGrid& grid, const std::string& sweep_dir,
                         const std::string& program, const SlurmOptions& options,
                         const SweepEventSink& on_event);

// "0-3,5,7-9": array indices (ascending) as sbatch's --array takes them.
std::string ArrayIndexList(const std::vector<size_t>& indices);

// The job id in sbatch --parsable's answer ("1234" or "1234;cluster").
std::string ParseSubmittedJob(const std::string& sbatch_output);

// Whether a Slurm job state is a wait in the queue (PENDING, or one of the REQUEUE states).
bool IsWaitingSlurmState(const std::string& state);

// Whether a Slurm job state is final (the task will not run again unless requeued by hand).
bool IsFinalSlurmState(const std::string& state);

}  // namespace cmbrl

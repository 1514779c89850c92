#include "cmbrl/sweep/slurm_engine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/subprocess.h"
#include "cmbrl/core/utc_time.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

constexpr const char* kSlurmJobsFile = "slurm-jobs.jsonl";

// The jobs this sweep submitted before, oldest first (sweep_dir/slurm-jobs.jsonl; an unfinished
// last line, from a stop mid-append, does not count).
std::vector<std::string> RecordedJobs(const std::string& sweep_dir) {
  const fs::path file = fs::path(sweep_dir) / kSlurmJobsFile;
  std::vector<std::string> jobs;
  std::istringstream lines(ReadWholeLines(file));
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    nlohmann::json record;
    try {
      record = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception&) {
      Fail("'{}' line {} is not JSON: expected a line that `cmbrl sweep --engine slurm` wrote",
           file.string(), number);
    }
    Require(record.is_object() && record.contains("job") && record["job"].is_string(),
            "'{}' line {} names no job: expected {{\"job\": \"1234\", ...}}", file.string(),
            number);
    jobs.push_back(record["job"].get<std::string>());
  }
  return jobs;
}

// squeue may fail for a while (the controller restarting); this many failures in a row end the
// wait with the last one's message.
constexpr int kSqueueFailuresTolerated = 10;

std::string Trimmed(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r\n") - begin + 1);
}

// Each array task of `job` that squeue still knows, with its state. A job that has left the
// controller's memory altogether ("Invalid job id") has no tasks left. Returns nullopt when
// squeue failed otherwise, with its message in `failure`.
std::optional<std::map<size_t, std::string>> QueuedTasks(const std::string& job,
                                                         std::string& failure) {
  const std::vector<std::string> args = {"--noheader", "--array", "--states=all", "--jobs=" + job,
                                         "--format=%K %T"};
  const ProgramOutput answer = RunProgram("squeue", args);
  std::map<size_t, std::string> tasks;
  if (answer.exit_code != 0) {
    if (answer.errors.find("Invalid job id") != std::string::npos) return tasks;
    failure = fmt::format("'{}' exited with {}: {}", CommandLine("squeue", args), answer.exit_code,
                          Trimmed(answer.errors));
    return std::nullopt;
  }
  std::istringstream lines(answer.output);
  std::string index, state;
  while (lines >> index >> state) {
    // A job submitted without an array shows "N/A"; ours always is one.
    if (index.find_first_not_of("0123456789") == std::string::npos) {
      tasks[std::stoul(index)] = state;
    }
  }
  return tasks;
}

}  // namespace

std::string ArrayIndexList(const std::vector<size_t>& indices) {
  std::string list;
  for (size_t first = 0; first < indices.size();) {
    size_t last = first;
    while (last + 1 < indices.size() && indices[last + 1] == indices[last] + 1) ++last;
    if (!list.empty()) list += ",";
    list += last == first ? std::to_string(indices[first])
                          : fmt::format("{}-{}", indices[first], indices[last]);
    first = last + 1;
  }
  return list;
}

std::string ParseSubmittedJob(const std::string& sbatch_output) {
  const std::string job = Trimmed(sbatch_output.substr(0, sbatch_output.find(';')));
  Require(!job.empty() && job.find_first_not_of("0123456789") == std::string::npos,
          "sbatch answered '{}': expected a job id (sbatch --parsable)", Trimmed(sbatch_output));
  return job;
}

bool IsWaitingSlurmState(const std::string& state) {
  return state == "PENDING" || state.rfind("REQUEUE", 0) == 0;  // REQUEUED, REQUEUE_HOLD, ...
}

bool IsFinalSlurmState(const std::string& state) {
  static constexpr std::array<const char*, 10> kFinal = {
      "COMPLETED", "FAILED",    "CANCELLED",     "TIMEOUT",  "NODE_FAIL",
      "PREEMPTED", "BOOT_FAIL", "OUT_OF_MEMORY", "DEADLINE", "REVOKED"};
  return std::find(kFinal.begin(), kFinal.end(), state) != kFinal.end();
}

namespace {

// Throws cmbrl::Error naming a bad poll interval, task limit or an sbatch option the sweep sets
// itself.
void CheckSlurmOptions(const SlurmOptions& options) {
  Require(options.poll_seconds > 0 && options.poll_seconds <= 3600,
          "the poll interval is {} s: expected more than 0 and at most 3600", options.poll_seconds);
  Require(options.max_running >= 0, "max_running is {}: expected 0 (no limit) or more",
          options.max_running);
  for (const std::string& arg : options.sbatch_args) {
    // The array's tasks are the sweep's unfinished runs, and sbatch's answer must be the job id.
    const auto is = [&](const std::string& flag) {
      return arg == flag || arg.rfind(flag + "=", 0) == 0;
    };
    Require(!is("--array") && !is("--parsable") && arg.rfind("-a", 0) != 0,
            "the sbatch option '{}' is the sweep's own: the array holds the unfinished runs "
            "(limit the tasks at a time with --jobs)",
            arg);
  }
}

// One submission of a sweep's unfinished runs as a Slurm array, and the following of its tasks
// to their end. Each run is the array task of its index; job_of_ says which job holds it.
class SlurmSweep {
 public:
  SlurmSweep(const SweepGrid& grid, const std::string& sweep_dir, const SlurmOptions& options,
             const std::vector<SweepRun>& runs, const SweepEventSink& on_event,
             SweepOutcome& outcome)
      : grid_(grid),
        sweep_dir_(sweep_dir),
        options_(options),
        runs_(runs),
        on_event_(on_event),
        outcome_(outcome) {}

  // The runs of `pending` whose task an earlier submission still has in the queue (submitting
  // them again would start a second writer of the run), reported as already queued; returns
  // the others.
  std::vector<size_t> LeaveOutQueued(const std::vector<size_t>& pending) {
    std::map<size_t, std::pair<std::string, std::string>> live;  // index -> (job, state)
    for (const std::string& job : RecordedJobs(sweep_dir_)) {
      std::string failure;
      const std::optional<std::map<size_t, std::string>> queued = QueuedTasks(job, failure);
      Require(queued.has_value(),
              "could not tell whether the sweep's earlier Slurm job {} still has tasks in the "
              "queue: {}; submitting now could run one task twice",
              job, failure);
      for (const auto& [index, state] : *queued) {
        if (!IsFinalSlurmState(state)) live[index] = {job, state};
      }
    }
    std::vector<size_t> to_submit;
    for (const size_t index : pending) {
      const auto found = live.find(index);
      if (found == live.end()) {
        to_submit.push_back(index);
        continue;
      }
      job_of_[index] = found->second.first;
      ++outcome_.already_queued;
      Report(index, "already queued", found->second.second);
    }
    return to_submit;
  }

  // Submits the runs of `indices` as one array job and records it in the sweep's jobs file.
  void Submit(const std::vector<size_t>& indices) {
    const fs::path script = fs::absolute(fs::path(sweep_dir_) / "slurm.sh");
    std::string array = ArrayIndexList(indices);
    if (options_.max_running > 0) array += fmt::format("%{}", options_.max_running);
    std::vector<std::string> args = {"--parsable", "--array=" + array};
    args.insert(args.end(), options_.sbatch_args.begin(), options_.sbatch_args.end());
    args.push_back(script.string());
    const ProgramOutput answer = RunProgram("sbatch", args);
    Require(answer.exit_code == 0, "'{}' exited with {}: {}", CommandLine("sbatch", args),
            answer.exit_code, Trimmed(answer.errors + answer.output));
    outcome_.job = ParseSubmittedJob(answer.output);
    outcome_.submitted = static_cast<int>(indices.size());
    AppendToFile(fs::path(sweep_dir_) / kSlurmJobsFile,
                 nlohmann::ordered_json{{"job", outcome_.job},
                                        {"array", array},
                                        {"submitted", UtcTimestamp()},
                                        {"sbatch_args", options_.sbatch_args}}
                         .dump() +
                     "\n");
    for (const size_t index : indices) {
      job_of_[index] = outcome_.job;
      Report(index, "submitted", "");
    }
  }

  // Follows the tasks of `pending` until each has ended: in a final state, or gone from the
  // queue. Throws cmbrl::Error once squeue has failed kSqueueFailuresTolerated times in a row.
  void Follow(std::vector<size_t> pending) {
    int failures_in_a_row = 0;
    while (!pending.empty()) {
      std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_seconds));
      std::map<std::string, std::map<size_t, std::string>> queued_by_job;
      std::string failure, failed_job;
      for (const size_t index : pending) {
        const std::string& job = job_of_[index];
        if (queued_by_job.count(job) != 0 || !failed_job.empty()) continue;
        std::optional<std::map<size_t, std::string>> queued = QueuedTasks(job, failure);
        if (queued) {
          queued_by_job[job] = std::move(*queued);
        } else {
          failed_job = job;
        }
      }
      if (!failed_job.empty()) {
        Require(++failures_in_a_row < kSqueueFailuresTolerated,
                "lost track of Slurm job {}: {} ({} times in a row); its tasks may still run: "
                "follow them with squeue, or run the sweep again once they have ended",
                failed_job, failure, failures_in_a_row);
        continue;
      }
      failures_in_a_row = 0;
      std::vector<size_t> still_pending;
      for (const size_t index : pending) {
        if (!Ended(index, queued_by_job[job_of_[index]])) still_pending.push_back(index);
      }
      pending = std::move(still_pending);
    }
  }

 private:
  // An event of run `index`'s array task.
  void Report(size_t index, const char* status, const std::string& state) {
    on_event_({runs_[index].name,
               status,
               (fs::path(sweep_dir_) / "logs" / fmt::format("slurm-{}.log", index)).string(),
               {},
               std::nullopt,
               std::nullopt,
               fmt::format("{}_{}", job_of_[index], index),
               state});
  }

  // Whether run `index`'s task has ended, given its job's tasks in the queue (`queued`), and if
  // so whether its run finished. Says when a task starts running, and when it waits in the
  // queue again after running (a requeue: its run resumes when it starts again); states in
  // between (COMPLETING while the old step is killed) may or may not be seen between two polls.
  bool Ended(size_t index, const std::map<size_t, std::string>& queued) {
    const auto queued_task = queued.find(index);
    if (queued_task != queued.end()) {
      const std::string& state = queued_task->second;
      if (state == "RUNNING" && running_.insert(index).second) {
        Report(index, "running", state);
      } else if (IsWaitingSlurmState(state) && running_.erase(index) != 0) {
        Report(index, "requeued", state);
      }
      last_state_[index] = state;
      if (!IsFinalSlurmState(state)) return false;
    }
    const SweepRun& run = runs_[index];
    const bool finished = StatusOf(run, grid_.steps) == RunStatus::kFinished;
    if (finished) {
      ++outcome_.finished_now;
    } else {
      outcome_.failed.push_back(run.name);
    }
    Report(index, finished ? "finished" : "failed",
           last_state_.count(index) != 0 ? last_state_[index] : "UNKNOWN");
    return true;
  }

  const SweepGrid& grid_;
  const std::string& sweep_dir_;
  const SlurmOptions& options_;
  const std::vector<SweepRun>& runs_;
  const SweepEventSink& on_event_;
  SweepOutcome& outcome_;
  std::map<size_t, std::string> job_of_;
  std::map<size_t, std::string> last_state_;
  std::set<size_t> running_;  // tasks seen running since they last waited in the queue
};

}  // namespace

SweepOutcome SubmitSweep(const SweepGrid& grid, const std::string& sweep_dir,
                         const std::string& program, const SlurmOptions& options,
                         const SweepEventSink& on_event) {
  CheckSlurmOptions(options);
  const PreparedSweep prepared = PrepareSweep(grid, sweep_dir, program, on_event);
  SweepOutcome outcome;
  outcome.runs = static_cast<int>(prepared.runs.size());
  outcome.already_finished = prepared.already_finished;
  if (prepared.unfinished.empty()) return outcome;
  SlurmSweep sweep(grid, sweep_dir, options, prepared.runs, on_event, outcome);
  const std::vector<size_t> to_submit = sweep.LeaveOutQueued(prepared.unfinished);
  if (!to_submit.empty()) sweep.Submit(to_submit);
  if (options.wait) sweep.Follow(prepared.unfinished);
  return outcome;
}

}  // namespace cmbrl

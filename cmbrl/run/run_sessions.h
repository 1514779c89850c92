// Where a run was made, session by session. The seed and the configuration fix a run's rows only
// on one setup: another CPU makes OpenBLAS pick other kernels, other thread counts split sums
// differently, another commit or library version computes differently, and a learning run
// amplifies the first differing bit into other episodes. A run directory therefore keeps one
// line per session (its start and every resume) in sessions.jsonl: when and at which step it
// began, and the setup it ran on. A resume on another setup is announced, and reports say where
// their runs were made.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cmbrl/run/run_directory.h"

namespace cmbrl {

// What besides the seed and the configuration decides a run's floating-point results.
struct NumericsSetup {
  std::string cmbrl;      // version and commit of the program, "0.1.0 (744c47e1a2b3)"
  std::string cpu;        // the CPU's model name from /proc/cpuinfo ("" where unknown)
  // The widest vector instructions the CPU offers the kernels: "avx512-bf16", "avx512", "avx2"
  // or "" (older, or a session of a version before v0.6). The model name alone does not tell
  // AMD EPYC generations apart, and oneDNN picks its kernels by this.
  std::string cpu_isa;
  std::string blas_core;  // the kernel set OpenBLAS runs, e.g. "Haswell" ("" without OpenBLAS)
  int blas_threads = 0;   // OpenBLAS's threads (0 without OpenBLAS)
  int torch_threads = 0;  // LibTorch's intra-op threads
  std::string libtorch;   // versions of the libraries that compute
  std::string mujoco;
  std::string xgboost;
  std::string onednn;  // "" without oneDNN (or before v0.6)
  std::string device;  // the run's device ("cpu", "cuda:0")
  // The Python functions the run plans with, "reward=module.f, termination=module.g" ("" for
  // none, and in sessions of versions before them): a session with others plans differently.
  std::string python_functions;

  bool operator==(const NumericsSetup& other) const;
  bool operator!=(const NumericsSetup& other) const { return !(*this == other); }
};


// One sentence-part per field that differs, "cpu 'AMD EPYC' -> 'Intel Xeon'"; empty when equal.
std::vector<std::string> SetupChanges(const NumericsSetup& before, const NumericsSetup& after);

// The setup in one line, for reports and messages.
std::string DescribeSetup(const NumericsSetup& setup);

// One session of a run: its start (number 1) or a resume.
struct RunSession {
  int number = 0;
  // The run's identity, drawn from the OS's entropy when the run began and repeated by every
  // session: a run folder copied or moved keeps it, so a report can tell a copy from another
  // seed. 32 hex digits; "" in sessions of versions before v0.7 (not part of any result).
  std::string run_id;
  std::string began;            // UTC, "2026-11-25T06:25:46Z"
  std::int64_t steps_done = 0;  // the run's agent (or environment) steps when it began
  NumericsSetup setup;
  // What a resume could not carry on exactly ("" for none), e.g. an episode under way started
  // again because the environment's state could not be saved (Learner::ResumeNote).
  std::string note;
};

// The sessions in run's sessions.jsonl, in order; empty when the file is absent (a run begun by
// a version that kept none). A last line left unfinished by a stop mid-write is not a session.
// Throws cmbrl::Error naming the file, the line and the key for any other malformed line, and
// for a line whose run id differs from an earlier line's.
std::vector<RunSession> ReadRunSessions(const RunDirectory& run);

// The run id its sessions carry ("" when none does: a run of a version before v0.7).
std::string RunIdOf(const std::vector<RunSession>& sessions);

// Appends a session that begins now at `steps_done` on `setup` (removing an unfinished last
// line first), with the run's id (a new one for the first session, or for a run whose earlier
// sessions kept none) and returns how its setup differs from the previous session's (empty for the
// first session, or when the run kept no sessions before). The caller holds the run's lock.
// Throws cmbrl::Error when the file cannot be read or written.
std::vector<std::string> RecordRunSession(const RunDirectory& run, std::int64_t steps_done,
                                          const NumericsSetup& setup,
                                          const std::string& note = "");

}  // namespace cmbrl

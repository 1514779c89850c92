// Running a sweep's grid on this machine: each run a separate `cmbrl train` process, a few at a
// time, each on CPUs of its own, skipping finished runs and resuming the others; the grid also
// goes to SWEEP_DIR/slurm.sh for a cluster. (sweep.h plans the grid; this starts processes.)
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/sweep/sweep.h"

namespace cmbrl {

// What happened to one run, as the sweep goes.
struct SweepEvent {
  std::string run;                // its name
  std::string status;             // "already finished", "started", "resumed", "finished", "failed"
  std::string log;                // its log file (started, resumed)
  std::vector<int> cpus;          // its CPUs (started, resumed; empty: it shares them all)
  std::optional<int> exit_code;   // finished, failed (128 + signal when killed)
  std::optional<double> seconds;  // finished, failed: wall time of this session
};

struct SweepOutcome {
  int runs = 0;
  int finished_now = 0;
  int already_finished = 0;
  std::vector<std::string> failed;
};

// Trains the grid into sweep_dir with `program` (the cmbrl executable) as `jobs` processes at a
// time, seeds outermost (every cell's first seed, then every cell's second, ...); `on_event` sees every run started, resumed, finished or failed. Training processes die
// with the sweep. Throws cmbrl::Error for a bad grid or a sweep_dir recorded with other
// settings; a failed run is reported in the outcome, not thrown.
SweepOutcome RunSweep(const SweepGrid& grid, const std::string& sweep_dir, int jobs,
                      const std::string& program,
                      const std::function<void(const SweepEvent&)>& on_event);

}  // namespace cmbrl

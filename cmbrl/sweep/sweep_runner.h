// The local engine: a sweep's grid on this machine, each run a separate `cmbrl train` process, a
// few at a time, each on CPUs of its own, skipping finished runs and resuming the others.
// (sweep.h plans the grid; slurm_engine.h submits it to a cluster instead.)
#pragma once

#include <string>

#include "cmbrl/sweep/sweep.h"

namespace cmbrl {

// Trains the grid into sweep_dir with `program` (the cmbrl executable) as `jobs` processes at a
// time, seeds outermost (every cell's first seed, then every cell's second, ...); `on_event` sees
// every run started, resumed, finished or failed. Training processes die with the sweep. Throws cmbrl::Error for a bad grid or a sweep_dir recorded with other
// settings; a failed run is reported in the outcome, not thrown.
SweepOutcome RunSweep(const SweepGrid& grid, const std::string& sweep_dir, int jobs,
                      const std::string& program, const SweepEventSink& on_event);

}  // namespace cmbrl

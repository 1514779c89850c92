// Running another program to its end and reading what it printed: the Slurm engine's sbatch,
// squeue and scontrol. (Training processes are started by the sweep's own spawner, which needs
// CPU shares and a log file instead.)
#pragma once

#include <string>
#include <vector>

namespace cmbrl {

struct ProgramOutput {
  int exit_code = 0;   // 128 + the signal's number when a signal ended it
  std::string output;  // what it wrote to standard output
  std::string errors;  // what it wrote to standard error
};

// Runs `program` (looked up on PATH) with `args`, waits for it and returns what it printed.
// Throws cmbrl::Error naming the program when it cannot be started (not on PATH, say). Thread-
// safe: it touches no shared state but the process table.
ProgramOutput RunProgram(const std::string& program, const std::vector<std::string>& args);

// "sbatch --parsable x.sh": the command line as a shell would show it, for messages.
std::string CommandLine(const std::string& program, const std::vector<std::string>& args);

}  // namespace cmbrl

// The subcommands of the `cmbrl` program. Each Add*Command registers its options on the parent
// and sets the callback that runs it.
#pragma once

#include <CLI/CLI.hpp>

namespace cmbrl::app {

void AddRolloutCommand(CLI::App& parent);
void AddTrainCommand(CLI::App& parent);
void AddEvalCommand(CLI::App& parent);
void AddBenchCommand(CLI::App& parent);
void AddSweepCommand(CLI::App& parent);
void AddReportCommand(CLI::App& parent);

}  // namespace cmbrl::app

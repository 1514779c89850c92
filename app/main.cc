// cmbrl: constrained model-based reinforcement learning (Robust Cross-Entropy MPC).
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "app/commands.h"
#include "cmbrl/core/process_setup.h"

int main(int argc, char** argv) {
  cmbrl::PrepareProcessForSpeed(argv);
  CLI::App app{
      "cmbrl: constrained model-based reinforcement learning with the Robust "
      "Cross-Entropy method on Safety Gym Goal tasks"};
  app.require_subcommand(1);
  cmbrl::app::AddRolloutCommand(app);
  cmbrl::app::AddTrainCommand(app);
  cmbrl::app::AddEvalCommand(app);
  cmbrl::app::AddBenchCommand(app);
  cmbrl::app::AddSweepCommand(app);
  cmbrl::app::AddReportCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const std::exception& error) {
    std::cerr << "cmbrl: error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}

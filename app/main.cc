// cmbrl: constrained model-based reinforcement learning (Robust Cross-Entropy MPC).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "cmbrl/core/build_info.h"
#include "cmbrl/core/process_setup.h"
#ifdef CMBRL_WITH_PYTHON
#include "python/bindings/embedded_python.h"
#endif

int main(int argc, char** argv) {
  cmbrl::PrepareProcessForSpeed(argv);
#ifdef CMBRL_WITH_PYTHON
  cmbrl::python::InstallEmbeddedPython();  // for configs that declare Python parts
#endif
  CLI::App app{
      "cmbrl: constrained model-based reinforcement learning with the Robust "
      "Cross-Entropy method, on Safety-Gymnasium's navigation tasks and your own environments"};
  app.set_version_flag("--version",
                       fmt::format("cmbrl {} ({})", cmbrl::CmbrlVersion(), cmbrl::CmbrlCommit()));
  app.require_subcommand(1);
  cmbrl::app::AddRolloutCommand(app);
  cmbrl::app::AddTrainCommand(app);
  cmbrl::app::AddEvalCommand(app);
  cmbrl::app::AddBenchCommand(app);
  cmbrl::app::AddSweepCommand(app);
  cmbrl::app::AddReportCommand(app);
  // CLI11 answers a mistyped command or bench subcommand with "A subcommand is required"; name
  // it instead, with the commands it could have been.
  const CLI::App* level = &app;
  std::string words;  // the commands named so far: "", "bench"
  for (int i = 1; i < argc && argv[i][0] != '-'; ++i) {
    std::vector<std::string> names;
    for (const CLI::App* command : level->get_subcommands({})) names.push_back(command->get_name());
    if (names.empty()) break;  // a command's own arguments follow
    const auto named = std::find(names.begin(), names.end(), argv[i]);
    const std::string said = words.empty() ? argv[i] : words + " " + argv[i];
    if (named == names.end()) {
      std::cerr << "cmbrl: error: unknown command '" << said << "': expected one of "
                << fmt::format("{}", fmt::join(names, ", ")) << " (cmbrl "
                << (words.empty() ? "" : words + " ") << "--help)\n";
      return 1;
    }
    level = level->get_subcommand(*named);
    words = said;
  }
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

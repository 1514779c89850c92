// The report tests' fixture: a sweep of small runs written in the learners' own log formats,
// and the original's logs in its format, in a folder of each test's own.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cmbrl/config/config.h"
#include "cmbrl/learners/mpc/mpc_learner.h"
#include "cmbrl/run/run_directory.h"
#include "tests/temp_path.h"

namespace cmbrl::testing {

// The paper's presets, which the setup notes compare runs with.
inline constexpr const char* kConfigs = CMBRL_SOURCE_DIR "/configs";

// A run of a fixture sweep: episodes of `steps` agent steps with the given costs; returns rise
// by one per episode from `first_return`. A run of a setting is named as a sweep names it;
// `adjust` changes its config before anything is written.
inline void WriteRun(const std::filesystem::path& sweep, const std::string& task,
                     const std::string& planner, std::uint64_t seed, int steps,
                     const std::vector<double>& costs, double first_return,
                     const std::string& setting = "",
                     const std::function<void(TrainConfig&)>& adjust = {}) {
  TrainConfig config;
  config.task = task;
  config.planner = planner;
  config.seed = seed;
  config.training.total_steps = 1000;
  if (adjust) adjust(config);
  const std::filesystem::path dir = sweep / "runs" /
                                    (setting.empty() ? fmt::format("{}-{}-s{}", task, planner, seed)
                                                     : SweepRunName(task, planner, setting, seed));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "config.yaml") << TrainConfigToYaml(config);
  std::ofstream progress(dir / "progress.csv");
  progress << ProgressCsvHeader() << "\n";
  for (size_t i = 0; i < costs.size(); ++i) {
    ProgressRow row;
    row.epoch = 1;
    row.episode = static_cast<int>(i) + 1;
    row.episode_return = first_return + static_cast<double>(i);
    row.episode_cost = costs[i];
    row.steps = steps;
    row.total_env_interacts = static_cast<std::int64_t>(steps) * (static_cast<int>(i) + 1);
    progress << ProgressCsvLine(row) << "\n";
  }
  progress.close();
  // A checkpoint that covers the rows, as a run writes one (empty of a learner's files).
  if (!costs.empty()) {
    WriteCheckpoint(RunDirectory(dir), static_cast<std::int64_t>(costs.size()), 0.0,
                    [](const std::filesystem::path&, const std::filesystem::path&) {});
  }
}

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A folder of this test's own (ctest runs the tests of this file as parallel processes).
    sweep_ = testing::TestTempPath("sweep");
    // Episodes of 100 steps. With a window of 300 the episodes starting at 0, 100 and 200 count.
    WriteRun(sweep_, "PointGoal1", "rce", 0, 100, {1, 0, 2, 9}, 0);  // 3 in the window
    WriteRun(sweep_, "PointGoal1", "rce", 1, 100, {0, 1, 0, 9}, 1);  // 1
    WriteRun(sweep_, "PointGoal1", "cem", 0, 100, {5, 5, 5, 5}, 0);  // 15
    WriteRun(sweep_, "PointGoal1", "cem", 1, 100, {6, 6, 6}, 2);     // 18
    WriteRun(sweep_, "CarGoal2", "rce", 0, 150, {4, 4, 4}, 0);       // starts 0, 150: 8
    WriteRun(sweep_, "CarGoal2", "cem", 0, 150, {1, 1, 1}, 0);       // 2
    WriteRun(sweep_, "CarGoal2", "cem", 1, 150, {}, 0);  // just started: no episode, left out
  }

  // The original's logs in its own format (no Steps column): PointGoal1 RCE seeds 0 and 10 with
  // episodes of 100 steps, and CarGoal2 CEM seed 0 too short for a window of 300.
  std::filesystem::path WriteReference() const {
    const std::filesystem::path dir = sweep_ / "reference";
    std::filesystem::create_directories(dir / "mbrl");
    const auto write = [&](const std::string& name, const std::vector<std::string>& rows) {
      std::ofstream out(dir / "mbrl" / name);
      out << "Epoch,Episode,EpRet,EpCost,TotalEnvInteracts,Time\n";
      for (const std::string& row : rows) out << row << "\n";
    };
    write("PointGoal1-rce-s0.csv",
          {"0,0,5,0,100,1", "0,1,6,1,200,2", "0,2,7,0,300,3", "0,3,8,4,400,4"});
    write("PointGoal1-rce-s10.csv", {"0,0,3,2,110,1", "0,1,4,2,190,2", "0,2,5,2,310,3"});
    write("CarGoal2-cem-s0.csv", {"0,0,1,7,150,1"});
    return dir;
  }
  std::filesystem::path sweep_;
};

}  // namespace cmbrl::testing

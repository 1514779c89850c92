#include "cmbrl/report/reference.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/report/table.h"
#include "tests/error_message.h"
#include "tests/report/report_fixture.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ReportTest;

TEST_F(ReportTest, BadReferenceLogsAreNamed) {
  const fs::path dir = WriteReference();
  std::ofstream(dir / "mbrl" / "PointGoal1-rce-s100.csv")
      << "Epoch,Episode,EpRet,EpCost,TotalEnvInteracts,Time\n0,0,1,1,100,1\n0,1,1,1,50,1\n";
  EXPECT_THAT(
      testing::ErrorMessage([&] { ReadReferenceRuns(dir.string()); }),
      HasSubstr("PointGoal1-rce-s100.csv line 3: TotalEnvInteracts is 50: expected a count of "
                "steps that never falls"));
  std::ofstream(dir / "mbrl" / "PointGoal1-rce-s100.csv") << "Epoch,EpRet\n";
  EXPECT_THAT(testing::ErrorMessage([&] { ReadReferenceRuns(dir.string()); }),
              HasSubstr("has no column EpCost"));
  fs::remove(dir / "mbrl" / "PointGoal1-rce-s100.csv");
  std::ofstream(dir / "mbrl" / "rce.csv") << "EpRet,EpCost,TotalEnvInteracts\n";
  EXPECT_THAT(testing::ErrorMessage([&] { ReadReferenceRuns(dir.string()); }),
              HasSubstr("expected a name <Task>-<planner>-s<seed>.csv"));
  EXPECT_THAT(testing::ErrorMessage([&] { ReadReferenceRuns((sweep_ / "nothing").string()); }),
              HasSubstr("expected the original's logs"));
}

TEST_F(ReportTest, ShippedReferenceLogsGiveTheOriginalsCounts) {
  // data/reference/ as shipped: the counts the original's README gives over 3000 and 10,000
  // agent steps (data/reference/), which the targets are built on.
  const std::vector<RunRecord> reference = ReadReferenceRuns(DefaultReferenceDir());
  ASSERT_EQ(reference.size(), 36u + 12u);  // 4 x 3 x 3 MPC runs, 4 x 3 model-free at limit 10
  const auto counts = [&](const std::string& task, const std::string& planner,
                          std::int64_t window) {
    std::vector<double> out;
    for (const RunRecord* run : ReferenceRunsOf(reference, task, planner)) {
      out.push_back(ViolationsWithin(*run, window));
    }
    return out;
  };
  EXPECT_EQ(counts("PointGoal2", "rce", 3000), (std::vector<double>{113, 78, 108}));
  EXPECT_EQ(counts("CarGoal2", "rce", 3000), (std::vector<double>{57, 21, 21}));
  EXPECT_EQ(counts("CarGoal1", "cem", 3000), (std::vector<double>{45, 31, 26}));
  EXPECT_EQ(counts("PointGoal1", "cem", 10000), (std::vector<double>{182, 157, 208}));
  EXPECT_EQ(counts("CarGoal2", "random", 10000), (std::vector<double>{460, 498, 523}));
  // A model-free log has a row per 30,000-step epoch: PointGoal1 TRPO's first epoch cost 2383,
  // so its count over 10,000 steps is interpolated to a third of it.
  const std::vector<double> trpo = counts("PointGoal1", "trpo", 10000);
  ASSERT_EQ(trpo.size(), 1u);
  EXPECT_NEAR(trpo[0], 2383.0 / 3, 1e-9);
  EXPECT_EQ(counts("PointGoal1", "trpo", 30000), (std::vector<double>{2383}));
  // The first epoch (10 episodes) of the original's CarGoal1 random runs: 8, 2 and 4 violations
  // with mean returns of 28.1, 27.9 and 29.8 (the level-2 ablations, at commit 95a7bdc).
  std::vector<double> violations, returns;
  for (const RunRecord* run : ReferenceRunsOf(reference, "CarGoal1", "random")) {
    const std::optional<FirstEpoch> first = FirstEpochOf(*run);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->episodes, 10);
    violations.push_back(first->violations);
    returns.push_back(std::round(first->mean_return * 10) / 10);
  }
  EXPECT_EQ(violations, (std::vector<double>{8, 2, 4}));
  EXPECT_EQ(returns, (std::vector<double>{28.1, 27.9, 29.8}));
}

// CMBRL_REFERENCE_DIR pointing nowhere is an error that names it, not a report without the
// comparison.
TEST(ReferenceTest, AReferenceFolderNamedByTheEnvironmentMustHoldTheLogs) {
  ASSERT_EQ(setenv("CMBRL_REFERENCE_DIR", "/nowhere/at/all", 1), 0);
  EXPECT_EQ(DefaultReferenceDir(), "/nowhere/at/all");
  try {
    ReadReferenceRuns(DefaultReferenceDir());
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("CMBRL_REFERENCE_DIR is '/nowhere/at/all'"));
  }
  unsetenv("CMBRL_REFERENCE_DIR");
}

}  // namespace
}  // namespace cmbrl

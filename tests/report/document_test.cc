#include "cmbrl/report/document.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/error_message.h"
#include "tests/report/report_fixture.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ReportTest;

// The report document is a library function: the files, the summary, the experiment's first
// tables, and the check of the runs before anything is written.
TEST_F(ReportTest, WriteReportWritesTheDocumentAndChecksTheRunsFirst) {
  ReportRequest request;
  request.sweep_dirs = {sweep_.string()};
  request.out = (sweep_ / "out").string();
  request.window = 300;
  request.reference = WriteReference().string();
  ExperimentStamp stamp;
  stamp.name = "fixture";
  stamp.dir = "experiments/fixture";
  stamp.file = "experiment.yaml";
  stamp.sha256 = std::string(64, 'a');
  stamp.family = "paper";
  request.experiment = stamp;
  const ReportSummary summary = WriteReport(request);
  EXPECT_EQ(summary.runs, 7u);
  EXPECT_EQ(summary.cells, 4u);
  EXPECT_EQ(summary.window, 300);
  for (const char* file :
       {"report.md", "table-1.md", "table-1.csv", "curves-epret.png", "curves-epcost.svg"}) {
    EXPECT_TRUE(fs::exists(sweep_ / "out" / file)) << file;
  }
  std::ifstream in(summary.report);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_THAT(text, HasSubstr("# Experiment report: fixture"));
  EXPECT_THAT(text, HasSubstr("SHA-256 " + std::string(64, 'a')));
  EXPECT_THAT(text, HasSubstr("## Outcome per task"));
  request.out = (sweep_ / "refused").string();
  request.check_runs = [](const std::vector<RunRecord>&) { Fail("not this experiment's"); };
  EXPECT_THAT(testing::ErrorMessage([&] { WriteReport(request); }),
              HasSubstr("not this experiment's"));
  EXPECT_FALSE(fs::exists(sweep_ / "refused"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/core/subprocess.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/error_message.h"

namespace cmbrl {
namespace {
using ::testing::HasSubstr;

TEST(SubprocessTest, ReturnsTheExitCodeAndBothStreams) {
  const ProgramOutput result = RunProgram("sh", {"-c", "echo out; echo err >&2; exit 3"});
  EXPECT_EQ(result.exit_code, 3);
  EXPECT_EQ(result.output, "out\n");
  EXPECT_EQ(result.errors, "err\n");
}

// Far more than a pipe holds (64 KiB) on both streams at once: read as it comes, no stall.
TEST(SubprocessTest, ReadsLargeOutputOnBothStreams) {
  const ProgramOutput result = RunProgram(
      "sh", {"-c", "head -c 1000000 /dev/zero | tr '\\0' a; head -c 700000 /dev/zero >&2"});
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.output.size(), 1000000u);
  EXPECT_EQ(result.output.find_first_not_of('a'), std::string::npos);
  EXPECT_EQ(result.errors.size(), 700000u);
}

TEST(SubprocessTest, AKillIsReportedAs128PlusTheSignal) {
  EXPECT_EQ(RunProgram("sh", {"-c", "kill -9 $$"}).exit_code, 128 + 9);
}

TEST(SubprocessTest, AMissingProgramIsAnErrorNamingIt) {
  EXPECT_THAT(testing::ErrorMessage([] { RunProgram("cmbrl-no-such-program", {"--x"}); }),
              HasSubstr("could not run 'cmbrl-no-such-program --x': No such file or directory "
                        "('cmbrl-no-such-program' is not on PATH)"));
}

}  // namespace
}  // namespace cmbrl

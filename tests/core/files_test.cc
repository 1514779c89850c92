#include "cmbrl/core/files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

TEST(FilesTest, WrittenAndAppendedTextReadsBack) {
  const std::string path = testing::TestTempPath("text");
  WriteFile(path, "one\n");
  AppendToFile(path, "two\n");
  EXPECT_EQ(ReadWholeLines(path), "one\ntwo\n");
}

// What an append stopped mid-line leaves: the unfinished line does not count.
TEST(FilesTest, AnUnfinishedLastLineIsNotRead) {
  const std::string path = testing::TestTempPath("cut");
  WriteFile(path, "one\ntwo\nthr");
  EXPECT_EQ(ReadWholeLines(path), "one\ntwo\n");
  WriteFile(path, "no newline at all");
  EXPECT_EQ(ReadWholeLines(path), "");
  EXPECT_EQ(ReadWholeLines(testing::TestTempPath("missing")), "");
}

TEST(FilesTest, AWriteIntoAMissingFolderNamesTheFileAndTheCause) {
  const std::string path = testing::TestTempPath("no-such-folder") + "/file";
  EXPECT_THAT(testing::ErrorMessage([&] { WriteFile(path, "x"); }),
              ::testing::HasSubstr("could not write '" + path + "': No such file or directory"));
}

}  // namespace
}  // namespace cmbrl

// A path of the running test's own: under the test temp folder, in a folder named after the
// process and the test, so that tests running in parallel processes (ctest --parallel, or two
// ctest runs at once) never write one file.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace cmbrl::testing {

inline std::string TestTempPath(const std::string& name) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) /
      ("cmbrl-" + std::to_string(::getpid()) + "-" + std::string(test->test_suite_name()) + "." +
       test->name());
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

}  // namespace cmbrl::testing

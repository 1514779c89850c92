// A folder of the running test's own: under the test temp folder, named after the process and the
// test, so that tests running in parallel processes (ctest --parallel, or two ctest runs at once)
// never write one file. The folder is removed when its test passes; when the test fails it is
// kept for a look, and its path is printed.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>

namespace cmbrl::testing {

// The folder of the test `suite`.`name` in this process (not created).
inline std::filesystem::path TestTempDirOf(const std::string& suite, const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) /
         ("cmbrl-" + std::to_string(::getpid()) + "-" + suite + "." + name);
}

// The running test's folder, created.
inline std::filesystem::path TestTempDir() {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = TestTempDirOf(test->test_suite_name(), test->name());
  std::filesystem::create_directories(dir);
  return dir;
}

// A path inside the running test's folder (the folder exists, the path need not).
inline std::string TestTempPath(const std::string& name) { return (TestTempDir() / name).string(); }

// Removes a test's folder after the test (a full test suite left about 90 MB in /tmp a run).
class TestTempDirCleaner : public ::testing::EmptyTestEventListener {
 public:
  void OnTestEnd(const ::testing::TestInfo& test) override {
    const std::filesystem::path dir = TestTempDirOf(test.test_suite_name(), test.name());
    std::error_code error;
    if (!std::filesystem::exists(dir, error)) return;
    if (test.result()->Failed()) {
      std::cerr << "[   KEPT   ] " << dir.string() << " (the failed test's files)\n";
      return;
    }
    std::filesystem::remove_all(dir, error);
    if (error) std::cerr << "[ LEFT OVER] " << dir.string() << ": " << error.message() << "\n";
  }
};

// Every test program that includes this header removes its tests' folders.
inline const bool kTestTempDirCleanerInstalled = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new TestTempDirCleaner);
  return true;
}();

}  // namespace cmbrl::testing

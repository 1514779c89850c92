#include "cmbrl/run/run_sessions.h"

#include <ATen/Parallel.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/version.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cmbrl/core/build_info.h"
#include "cmbrl/models/onednn_forward.h"
#include "cmbrl/train/current_setup.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using testing::ErrorMessage;
using ::testing::HasSubstr;
using ::testing::StartsWith;

// A run directory in the test's own folder (removed when the test passes).
RunDirectory TempRun(const std::string& name) {
  const fs::path dir = testing::TestTempPath(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return RunDirectory(dir);
}

NumericsSetup SomeSetup() {
  NumericsSetup setup;
  setup.cmbrl = "0.1.0 (abc)";
  setup.cpu = "AMD EPYC";
  setup.cpu_isa = "avx2";
  setup.blas_core = "Haswell";
  setup.blas_threads = 1;
  setup.torch_threads = 1;
  setup.libtorch = "1.13.0";
  setup.mujoco = "2.2.2";
  setup.xgboost = "1.7.4";
  setup.onednn = "2.6.3";
  setup.device = "cpu";
  return setup;
}

void Append(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::app);
  out << text;
}

TEST(RunSessionsTest, ThisProcessSetupNamesItsProgramLibrariesAndThreads) {
  const NumericsSetup setup = CurrentNumericsSetup("cpu");
  EXPECT_THAT(setup.cmbrl, StartsWith(std::string(CmbrlVersion()) + " ("));
  EXPECT_THAT(setup.cmbrl, HasSubstr(CmbrlCommit()));
  EXPECT_EQ(setup.libtorch, TORCH_VERSION);
  EXPECT_THAT(setup.mujoco, StartsWith("2."));
  EXPECT_THAT(setup.xgboost, StartsWith("1."));
  EXPECT_EQ(setup.torch_threads, at::get_num_threads());
  EXPECT_EQ(setup.device, "cpu");
  // Every x86-64 CPU these builds run on has at least AVX2 (the development and CI machines do).
  EXPECT_THAT(setup.cpu_isa, ::testing::AnyOf("avx2", "avx512", "avx512-bf16"));
  EXPECT_EQ(setup.onednn, OnednnVersion());
  // The CPU's name where /proc/cpuinfo gives one (x86 Linux does).
  std::ifstream cpuinfo("/proc/cpuinfo");
  const std::string text((std::istreambuf_iterator<char>(cpuinfo)),
                         std::istreambuf_iterator<char>());
  if (text.find("model name") != std::string::npos) {
    EXPECT_FALSE(setup.cpu.empty());
  }
}

TEST(RunSessionsTest, ChangesNameEachFieldThatDiffers) {
  NumericsSetup other = SomeSetup();
  EXPECT_TRUE(SetupChanges(SomeSetup(), other).empty());
  EXPECT_EQ(SomeSetup(), other);
  other.cpu = "Intel Xeon";
  other.cpu_isa = "avx512";
  other.torch_threads = 2;
  EXPECT_THAT(SetupChanges(SomeSetup(), other),
              ElementsAre("cpu 'AMD EPYC' -> 'Intel Xeon'", "cpu_isa 'avx2' -> 'avx512'",
                          "torch_threads '1' -> '2'"));
  EXPECT_NE(SomeSetup(), other);
  EXPECT_THAT(DescribeSetup(other),
              HasSubstr("CPU 'Intel Xeon' (avx512), OpenBLAS kernels 'Haswell'"));
}

TEST(RunSessionsTest, SessionsOfVersionsBeforeTheIsaWasRecordedStillRead) {
  const RunDirectory run = TempRun("older");
  Append(run.sessions_file(),
         "{\"session\":1,\"began\":\"2026-11-25T06:25:46Z\",\"steps_done\":0,\"cmbrl\":\"0.1.0 "
         "(abc)\",\"cpu\":\"AMD EPYC\",\"blas_core\":\"Zen\",\"blas_threads\":1,"
         "\"torch_threads\":1,\"libtorch\":\"1.13.0\",\"mujoco\":\"2.2.2\",\"xgboost\":"
         "\"1.7.4\",\"device\":\"cpu\"}\n");
  const std::vector<RunSession> sessions = ReadRunSessions(run);
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].setup.cpu_isa, "");
  EXPECT_EQ(sessions[0].setup.onednn, "");
  // A resume by a version that records them names what it now knows.
  EXPECT_THAT(RecordRunSession(run, 100, SomeSetup()),
              ::testing::Contains("cpu_isa '' -> 'avx2'"));
}

TEST(RunSessionsTest, EachSessionIsALineAndAResumeElsewhereIsNamed) {
  const RunDirectory run = TempRun("record");
  EXPECT_TRUE(ReadRunSessions(run).empty()) << "no file: a run that kept no sessions";
  EXPECT_TRUE(RecordRunSession(run, 0, SomeSetup()).empty());
  EXPECT_TRUE(RecordRunSession(run, 120, SomeSetup()).empty());
  NumericsSetup elsewhere = SomeSetup();
  elsewhere.blas_core = "SkylakeX";
  EXPECT_THAT(RecordRunSession(run, 250, elsewhere),
              ElementsAre("blas_core 'Haswell' -> 'SkylakeX'"));
  const std::vector<RunSession> sessions = ReadRunSessions(run);
  ASSERT_EQ(sessions.size(), 3u);
  EXPECT_EQ(sessions[0].number, 1);
  EXPECT_EQ(sessions[2].number, 3);
  EXPECT_EQ(sessions[1].steps_done, 120);
  EXPECT_EQ(sessions[0].setup, SomeSetup());
  EXPECT_EQ(sessions[2].setup, elsewhere);
  // "2026-11-25T06:25:46Z"
  EXPECT_EQ(sessions[0].began.size(), 20u);
  EXPECT_EQ(sessions[0].began.back(), 'Z');
}

// A run's id is drawn once and repeated by each session; another run draws another; a run of a
// version that kept none gets one from its next session; a line of another run is refused.
TEST(RunSessionsTest, EverySessionCarriesTheRunsOneId) {
  const RunDirectory run = TempRun("id");
  RecordRunSession(run, 0, SomeSetup());
  RecordRunSession(run, 100, SomeSetup());
  const std::vector<RunSession> sessions = ReadRunSessions(run);
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[0].run_id.size(), 32u);
  EXPECT_EQ(sessions[1].run_id, sessions[0].run_id);
  EXPECT_EQ(RunIdOf(sessions), sessions[0].run_id);

  const RunDirectory other = TempRun("id_other");
  RecordRunSession(other, 0, SomeSetup());
  EXPECT_NE(RunIdOf(ReadRunSessions(other)), RunIdOf(sessions));

  const RunDirectory older = TempRun("id_older");  // a v0.6 line: no "run"
  Append(older.sessions_file(),
         R"({"session":1,"began":"2026-11-25T06:25:46Z","steps_done":0,"cmbrl":"0.1.0",)"
         R"("cpu":"c","blas_core":"b","blas_threads":1,"torch_threads":1,"libtorch":"l",)"
         R"("mujoco":"m","xgboost":"x","device":"cpu"})"
         "\n");
  EXPECT_EQ(RunIdOf(ReadRunSessions(older)), "");
  RecordRunSession(older, 100, SomeSetup());
  EXPECT_EQ(RunIdOf(ReadRunSessions(older)).size(), 32u);

  std::string joined;
  {
    std::ifstream in(other.sessions_file());
    std::getline(in, joined);
  }
  Append(run.sessions_file(), joined + "\n");
  EXPECT_THAT(ErrorMessage([&] { ReadRunSessions(run); }),
              HasSubstr("sessions.jsonl' line 3: run '" + RunIdOf(ReadRunSessions(other)) +
                        "' where the earlier lines have run '" + RunIdOf(sessions) + "'"));
}

// A stop while a line was written leaves it unfinished: it is no session, and the next one
// takes its place.
TEST(RunSessionsTest, AnUnfinishedLastLineIsDropped) {
  const RunDirectory run = TempRun("unfinished");
  RecordRunSession(run, 0, SomeSetup());
  Append(run.sessions_file(), "{\"session\":2,\"began\":\"2026-");
  ASSERT_EQ(ReadRunSessions(run).size(), 1u);
  RecordRunSession(run, 300, SomeSetup());
  const std::vector<RunSession> sessions = ReadRunSessions(run);
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[1].number, 2);
  EXPECT_EQ(sessions[1].steps_done, 300);
}

TEST(RunSessionsTest, AMalformedLineIsNamedWithItsKey) {
  const RunDirectory run = TempRun("malformed");
  RecordRunSession(run, 0, SomeSetup());
  Append(run.sessions_file(), "{\"session\":2,\"began\":\"x\",\"steps_done\":\"many\"}\n");
  EXPECT_THAT(ErrorMessage([&] { ReadRunSessions(run); }),
              HasSubstr("sessions.jsonl' line 2: 'steps_done' is \"many\": expected a whole "
                        "number"));
  const RunDirectory other = TempRun("missing_key");
  Append(other.sessions_file(), "{\"session\":1,\"began\":\"x\",\"steps_done\":0}\n");
  EXPECT_THAT(ErrorMessage([&] { ReadRunSessions(other); }),
              HasSubstr("line 1: no 'cmbrl': expected a session with its setup"));
  const RunDirectory garbled = TempRun("garbled");
  Append(garbled.sessions_file(), "not json\n");
  EXPECT_THAT(ErrorMessage([&] { ReadRunSessions(garbled); }), HasSubstr("line 1: not JSON"));
}

}  // namespace
}  // namespace cmbrl

#include "cmbrl/sweep/slurm_engine.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cmbrl/core/files.h"
#include "tests/error_message.h"
#include "tests/temp_path.h"

namespace cmbrl {
namespace {
namespace fs = std::filesystem;
using ::testing::ElementsAre;
using testing::ErrorMessage;
using ::testing::HasSubstr;

std::string Read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Stand-ins for Slurm's sbatch and squeue, first on PATH while the test runs. Each records its
// arguments beside itself; squeue answers from the script `squeue_body` (bash) given, which
// sees its call number as $call and the folder as $dir.
class FakeSlurm {
 public:
  FakeSlurm(const std::string& sbatch_body, const std::string& squeue_body)
      : dir_(testing::TestTempPath("fake-slurm")), old_path_(std::getenv("PATH")) {
    fs::create_directories(dir_);
    Write("sbatch", sbatch_body);
    Write("squeue", squeue_body);
    setenv("PATH", (dir_.string() + ":" + old_path_).c_str(), 1);
  }
  ~FakeSlurm() { setenv("PATH", old_path_.c_str(), 1); }
  FakeSlurm(const FakeSlurm&) = delete;
  FakeSlurm& operator=(const FakeSlurm&) = delete;

  std::string args(const std::string& program) const { return Read(dir_ / (program + ".args")); }
  int calls(const std::string& program) const {
    return fs::exists(dir_ / (program + ".calls")) ? std::stoi(Read(dir_ / (program + ".calls")))
                                                   : 0;
  }

 private:
  void Write(const std::string& program, const std::string& body) {
    const fs::path path = dir_ / program;
    std::ofstream(path) << "#!/bin/bash\n"
                        << "dir='" << dir_.string() << "'\n"
                        << "call=$(( $(cat \"$dir/" << program << ".calls\" 2>/dev/null || echo 0)"
                        << " + 1 ))\n"
                        << "echo $call > \"$dir/" << program << ".calls\"\n"
                        << "echo \"$@\" > \"$dir/" << program << ".args\"\n"
                        << body << "\n";
    fs::permissions(path, fs::perms::owner_all);
  }
  fs::path dir_;
  std::string old_path_;
};

// A run that reached 3000 steps: the logs of one the CPU grid made (committed in its report).
const char* kFinishedRun =
    CMBRL_SOURCE_DIR "/experiments/cpu-grid/report/run-logs/pointgoal1-rce-s0";

// Options that follow the array to its end, polling the fake squeue every 10 ms.
SlurmOptions Waiting() {
  SlurmOptions options;
  options.wait = true;
  options.poll_seconds = 0.01;
  return options;
}

SweepGrid TwoSeeds() {
  SweepGrid grid;
  grid.tasks = {"PointGoal1"};
  grid.planners = {"rce"};
  grid.seeds = {0, 1};
  grid.config_dir = CMBRL_SOURCE_DIR "/configs";
  grid.steps = 3000;
  return grid;
}

struct Recorded {
  std::vector<SweepEvent> events;
  SweepEventSink sink() {
    return [this](const SweepEvent& event) { events.push_back(event); };
  }
  // "run status job state" per event, in order.
  std::vector<std::string> lines() const {
    std::vector<std::string> out;
    for (const SweepEvent& event : events) {
      out.push_back(event.run + " " + event.status + " " + event.job + " " + event.state);
    }
    return out;
  }
};

TEST(SlurmEngineTest, ArrayIndicesAreGivenAsRanges) {
  EXPECT_EQ(ArrayIndexList({0, 1, 2, 3}), "0-3");
  EXPECT_EQ(ArrayIndexList({0, 2, 3, 4, 7, 9, 10}), "0,2-4,7,9-10");
  EXPECT_EQ(ArrayIndexList({5}), "5");
}

TEST(SlurmEngineTest, TheJobIdIsReadFromSbatchsAnswer) {
  EXPECT_EQ(ParseSubmittedJob("1234\n"), "1234");
  EXPECT_EQ(ParseSubmittedJob("1234;cluster-a\n"), "1234");
  EXPECT_THAT(ErrorMessage([] { ParseSubmittedJob("Submitted batch job 12"); }),
              HasSubstr("sbatch answered 'Submitted batch job 12': expected a job id"));
}

TEST(SlurmEngineTest, OnlyEndedStatesAreFinal) {
  for (const char* state :
       {"COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY"}) {
    EXPECT_TRUE(IsFinalSlurmState(state)) << state;
  }
  for (const char* state : {"PENDING", "RUNNING", "REQUEUED", "COMPLETING", "SUSPENDED"}) {
    EXPECT_FALSE(IsFinalSlurmState(state)) << state;
  }
  for (const char* state : {"PENDING", "REQUEUED", "REQUEUE_HOLD", "REQUEUE_FED"}) {
    EXPECT_TRUE(IsWaitingSlurmState(state)) << state;
  }
  for (const char* state : {"RUNNING", "COMPLETING", "COMPLETED", "SUSPENDED"}) {
    EXPECT_FALSE(IsWaitingSlurmState(state)) << state;
  }
}

// The array is submitted once with our options and the caller's; the wait outlasts a failing
// squeue, and each run is judged by its own progress, whatever Slurm's state says.
TEST(SlurmEngineTest, SubmitsTheUnfinishedRunsAndFollowsThemToTheirEnd) {
  const std::string sweep_dir = testing::TestTempPath("sweep");
  const std::string run0 = sweep_dir + "/runs/pointgoal1-rce-s0";
  const FakeSlurm slurm("echo '4242;cluster'",
                        "case $call in\n"
                        "  1) printf '0 RUNNING\\n1 PENDING\\n';;\n"
                        "  2) echo 'squeue: error: Socket timed out' >&2; exit 1;;\n"
                        "  3) printf '0 COMPLETING\\n1 RUNNING\\n';;\n"  // 0 requeued
                        "  4) printf '0 REQUEUED\\n1 RUNNING\\n';;\n"
                        "  5) printf '0 RUNNING\\n1 RUNNING\\n';;\n"
                        // Task 0's run reaches its budget; task 1 is cancelled.
                        "  *) cp -r '" +
                            std::string(kFinishedRun) + "' '" + run0 +
                            "'\n"
                            "     printf '0 COMPLETED\\n1 CANCELLED\\n';;\n"
                            "esac");
  SlurmOptions options = Waiting();
  options.sbatch_args = {"--partition=short"};
  options.max_running = 1;
  Recorded recorded;
  const SweepOutcome outcome =
      SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", options, recorded.sink());

  EXPECT_EQ(slurm.args("sbatch"), "--parsable --array=0-1%1 --partition=short " +
                                      fs::absolute(sweep_dir + "/slurm.sh").string() + "\n");
  EXPECT_THAT(slurm.args("squeue"), HasSubstr("--array --states=all --jobs=4242 --format=%K %T"));
  EXPECT_EQ(slurm.calls("squeue"), 6);
  EXPECT_EQ(outcome.job, "4242");
  EXPECT_EQ(outcome.submitted, 2);
  EXPECT_EQ(outcome.finished_now, 1);
  EXPECT_THAT(outcome.failed, ElementsAre("pointgoal1-rce-s1"));
  EXPECT_THAT(recorded.lines(), ElementsAre("pointgoal1-rce-s0 submitted 4242_0 ",
                                            "pointgoal1-rce-s1 submitted 4242_1 ",
                                            "pointgoal1-rce-s0 running 4242_0 RUNNING",
                                            "pointgoal1-rce-s1 running 4242_1 RUNNING",
                                            "pointgoal1-rce-s0 requeued 4242_0 REQUEUED",
                                            "pointgoal1-rce-s0 running 4242_0 RUNNING",
                                            "pointgoal1-rce-s0 finished 4242_0 COMPLETED",
                                            "pointgoal1-rce-s1 failed 4242_1 CANCELLED"));
  EXPECT_EQ(recorded.events[1].log, sweep_dir + "/logs/slurm-1.log");
  EXPECT_THAT(Read(sweep_dir + "/slurm-jobs.jsonl"),
              HasSubstr(R"({"job":"4242","array":"0-1%1","submitted":")"));
  EXPECT_THAT(Read(sweep_dir + "/slurm.sh"), HasSubstr("#SBATCH --requeue\n"));
}

// Submitted again, the finished run is skipped and only the other is sent.
TEST(SlurmEngineTest, ASecondSubmissionSendsOnlyWhatIsUnfinished) {
  const std::string sweep_dir = testing::TestTempPath("sweep");
  fs::create_directories(sweep_dir + "/runs");
  fs::copy(kFinishedRun, sweep_dir + "/runs/pointgoal1-rce-s0", fs::copy_options::recursive);
  const FakeSlurm slurm("echo 77", "exit 0");
  Recorded recorded;
  const SweepOutcome outcome =
      SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", SlurmOptions{}, recorded.sink());
  EXPECT_THAT(slurm.args("sbatch"), HasSubstr("--parsable --array=1 "));
  EXPECT_EQ(slurm.calls("squeue"), 0);  // not asked to wait
  EXPECT_EQ(outcome.already_finished, 1);
  EXPECT_EQ(outcome.submitted, 1);
  ASSERT_EQ(recorded.events.size(), 2u);
  EXPECT_EQ(recorded.events[0].status, "already finished");
  EXPECT_EQ(recorded.events[1].job, "77_1");

  // Every run finished: nothing is submitted.
  fs::copy(kFinishedRun, sweep_dir + "/runs/pointgoal1-rce-s1", fs::copy_options::recursive);
  const SweepOutcome again =
      SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", SlurmOptions{}, recorded.sink());
  EXPECT_EQ(slurm.calls("sbatch"), 1);
  EXPECT_EQ(again.submitted, 0);
  EXPECT_EQ(again.job, "");
}

// Submitted again while a task of the first submission is still in the queue, the sweep follows
// that task instead of starting a second writer of its run, and submits only the others.
TEST(SlurmEngineTest, ATaskStillQueuedFromAnEarlierSubmissionIsFollowedNotSubmittedAgain) {
  const std::string sweep_dir = testing::TestTempPath("sweep");
  const FakeSlurm slurm("echo $((100 + call))",
                        "if [ $call = 1 ]; then printf '0 RUNNING\\n1 COMPLETED\\n'; exit; fi\n"
                        "case \"$*\" in\n"
                        "  *--jobs=101*) printf '0 COMPLETED\\n';;\n"
                        "  *--jobs=102*) printf '1 CANCELLED\\n';;\n"
                        "esac");
  SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", SlurmOptions{}, [](auto&) {});  // job 101
  const SlurmOptions options = Waiting();
  Recorded recorded;
  const SweepOutcome outcome =
      SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", options, recorded.sink());
  EXPECT_THAT(slurm.args("sbatch"), HasSubstr("--parsable --array=1 "));
  EXPECT_EQ(outcome.already_queued, 1);
  EXPECT_EQ(outcome.submitted, 1);
  EXPECT_EQ(outcome.job, "102");
  EXPECT_THAT(recorded.lines(), ElementsAre("pointgoal1-rce-s0 already queued 101_0 RUNNING",
                                            "pointgoal1-rce-s1 submitted 102_1 ",
                                            "pointgoal1-rce-s0 failed 101_0 COMPLETED",
                                            "pointgoal1-rce-s1 failed 102_1 CANCELLED"));
  // A damaged record of the jobs is named, not guessed around.
  AppendToFile(sweep_dir + "/slurm-jobs.jsonl", "{\"array\": \"0-1\"}\n");
  EXPECT_THAT(ErrorMessage([&] {
                SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", SlurmOptions{}, [](auto&) {});
              }),
              HasSubstr("slurm-jobs.jsonl' line 3 names no job"));
}

TEST(SlurmEngineTest, SlurmsRefusalsAreErrorsThatQuoteIt) {
  const std::string sweep_dir = testing::TestTempPath("sweep");
  {
    const FakeSlurm slurm("echo 'sbatch: error: invalid partition specified: gpu' >&2; exit 1",
                          "exit 0");
    EXPECT_THAT(ErrorMessage([&] {
                  SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", SlurmOptions{}, [](auto&) {});
                }),
                HasSubstr("exited with 1: sbatch: error: invalid partition specified: gpu"));
  }
  {
    const FakeSlurm slurm("echo 5",
                          "echo 'squeue: error: Unable to contact slurm controller' >&2; exit 1");
    const SlurmOptions options = Waiting();
    EXPECT_THAT(
        ErrorMessage(
            [&] { SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", options, [](auto&) {}); }),
        HasSubstr("lost track of Slurm job 5: 'squeue --noheader --array --states=all --jobs=5 "
                  "--format=%K %T' exited with 1: squeue: error: Unable to contact slurm "
                  "controller (10 times in a row)"));
  }
  {
    // A job the controller has forgotten has no tasks left: the wait ends.
    const FakeSlurm slurm("echo 6",
                          "echo 'slurm_load_jobs error: Invalid job id specified' >&2; exit 1");
    const SlurmOptions options = Waiting();
    Recorded recorded;
    const SweepOutcome outcome =
        SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", options, recorded.sink());
    EXPECT_EQ(outcome.failed.size(), 2u);
    EXPECT_EQ(recorded.events.back().state, "UNKNOWN");
  }
  for (const char* ours : {"--array=0-3", "-a0-3", "--parsable"}) {
    SlurmOptions options;
    options.sbatch_args = {"--partition=short", ours};
    EXPECT_THAT(ErrorMessage([&] {
                  SubmitSweep(TwoSeeds(), sweep_dir, "/opt/cmbrl", options, [](auto&) {});
                }),
                HasSubstr(std::string("the sbatch option '") + ours + "' is the sweep's own"));
  }
  const std::string old_path = std::getenv("PATH");
  setenv("PATH", testing::TestTempPath("empty").c_str(), 1);
  const std::string missing = ErrorMessage([&] {
    SubmitSweep(TwoSeeds(), testing::TestTempPath("new-sweep"), "/opt/cmbrl", SlurmOptions{},
                [](auto&) {});
  });
  setenv("PATH", old_path.c_str(), 1);
  EXPECT_THAT(missing, HasSubstr("('sbatch' is not on PATH)"));
}

}  // namespace
}  // namespace cmbrl

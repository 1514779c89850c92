#include "cmbrl/report/reference.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include "cmbrl/core/check.h"

#ifndef CMBRL_SOURCE_DATA_DIR
#define CMBRL_SOURCE_DATA_DIR "data"
#endif

namespace cmbrl {
namespace fs = std::filesystem;

std::string DefaultReferenceDir() {
  const char* overridden = std::getenv("CMBRL_REFERENCE_DIR");
  if (overridden != nullptr && *overridden != '\0') return overridden;
  return std::string(CMBRL_SOURCE_DATA_DIR) + "/reference";
}

std::string DefaultConfigsDir() {
  // The data folder's sibling: the source tree's configs/.
  return (fs::path(CMBRL_SOURCE_DATA_DIR).parent_path() / "configs").string();
}

std::vector<RunRecord> ReadReferenceRuns(const std::string& dir) {
  const fs::path folder = fs::path(dir) / "mbrl";
  const char* from_environment = std::getenv("CMBRL_REFERENCE_DIR");
  Require(fs::is_directory(folder),
          "'{}' is not a folder: expected the original's logs (data/reference/mbrl of the source "
          "tree){}",
          folder.string(),
          from_environment != nullptr && *from_environment != '\0'
              ? fmt::format("; CMBRL_REFERENCE_DIR is '{}': unset it or point it at them",
                            from_environment)
              : std::string("; give --reference DIR or set CMBRL_REFERENCE_DIR"));
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() == ".csv") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  static const std::regex kName(R"(([A-Za-z0-9]+)-([a-z]+)-s([0-9]+))");
  std::vector<RunRecord> runs;
  for (const fs::path& file : files) {
    std::smatch match;
    const std::string stem = file.stem().string();
    Require(std::regex_match(stem, match, kName),
            "'{}': expected a name <Task>-<planner>-s<seed>.csv", file.string());
    RunRecord run;
    run.name = "original " + stem;
    run.config.task = match[1];
    run.config.planner = match[2];
    run.config.seed = std::stoull(match[3]);
    run.episodes = ReadEpisodeColumns(file.string(), /*has_steps=*/false);
    runs.push_back(std::move(run));
  }
  // The model-free baselines of the paper's main comparison (cost limit 10, one seed each);
  // the appendix's other limits are not compared here.
  const fs::path model_free = fs::path(dir) / "model-free";
  if (fs::is_directory(model_free)) {
    static const std::regex kModelFreeName(R"(([A-Za-z0-9]+)-([a-z-]+)-limit10)");
    std::vector<fs::path> logs;
    for (const fs::directory_entry& entry : fs::directory_iterator(model_free)) {
      if (entry.path().extension() == ".csv") logs.push_back(entry.path());
    }
    std::sort(logs.begin(), logs.end());
    for (const fs::path& file : logs) {
      std::smatch match;
      const std::string stem = file.stem().string();
      if (!std::regex_match(stem, match, kModelFreeName)) continue;
      RunRecord run;
      run.name = "original " + stem;
      run.config.task = match[1];
      run.config.algorithm = match[2];
      run.config.variant = Variant::kPaperLidar;
      run.epoch_log = true;
      run.episodes = ReadEpochLog(file.string());
      runs.push_back(std::move(run));
    }
  }
  return runs;
}

std::vector<const RunRecord*> ReferenceRunsOf(const std::vector<RunRecord>& reference,
                                              const std::string& task, const std::string& planner) {
  std::vector<const RunRecord*> found;
  for (const RunRecord& run : reference) {
    if (run.config.task == task && MethodOf(run.config) == planner) found.push_back(&run);
  }
  std::sort(found.begin(), found.end(), [](const RunRecord* a, const RunRecord* b) {
    return a->config.seed < b->config.seed;
  });
  return found;
}

}  // namespace cmbrl

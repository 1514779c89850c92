#include "cmbrl/run/run_sessions.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/core/utc_time.h"

namespace cmbrl {
namespace {

namespace fs = std::filesystem;

// A setup's fields as sessions.jsonl writes them, in one order: also what SetupChanges compares.
nlohmann::ordered_json SetupJson(const NumericsSetup& setup) {
  return {{"cmbrl", setup.cmbrl},
          {"cpu", setup.cpu},
          {"cpu_isa", setup.cpu_isa},
          {"blas_core", setup.blas_core},
          {"blas_threads", setup.blas_threads},
          {"torch_threads", setup.torch_threads},
          {"libtorch", setup.libtorch},
          {"mujoco", setup.mujoco},
          {"xgboost", setup.xgboost},
          {"onednn", setup.onednn},
          {"device", setup.device},
          {"python_functions", setup.python_functions}};
}

nlohmann::ordered_json SessionJson(const RunSession& session) {
  nlohmann::ordered_json line = {{"session", session.number}, {"run", session.run_id},
                                 {"began", session.began}, {"steps_done", session.steps_done}};
  line.update(SetupJson(session.setup));
  if (!session.note.empty()) line["note"] = session.note;
  return line;
}

// A value of the line's object, named in the error when it is missing or of another type.
template <typename T>
T Field(const nlohmann::json& line, const char* key, const std::string& where) {
  const auto it = line.find(key);
  Require(it != line.end(), "{}: no '{}': expected a session with its setup", where, key);
  try {
    return it->get<T>();
  } catch (const nlohmann::json::exception&) {
    Fail("{}: '{}' is {}: expected {}", where, key, it->dump(),
         std::is_same_v<T, std::string> ? "a string" : "a whole number");
  }
}

// The same for a field that sessions of older versions do not have: "" when absent.
std::string OptionalText(const nlohmann::json& line, const char* key, const std::string& where) {
  return line.contains(key) ? Field<std::string>(line, key, where) : std::string();
}

RunSession ParseSession(const std::string& text, const std::string& where) {
  nlohmann::json line;
  try {
    line = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    Fail("{}: not JSON ({}): expected one session per line", where, error.what());
  }
  Require(line.is_object(), "{}: {} is not an object: expected one session per line", where, text);
  RunSession session;
  session.number = Field<int>(line, "session", where);
  session.run_id = OptionalText(line, "run", where);
  session.began = Field<std::string>(line, "began", where);
  session.steps_done = Field<std::int64_t>(line, "steps_done", where);
  NumericsSetup& setup = session.setup;
  setup.cmbrl = Field<std::string>(line, "cmbrl", where);
  setup.cpu = Field<std::string>(line, "cpu", where);
  setup.cpu_isa = OptionalText(line, "cpu_isa", where);
  setup.blas_core = Field<std::string>(line, "blas_core", where);
  setup.blas_threads = Field<int>(line, "blas_threads", where);
  setup.torch_threads = Field<int>(line, "torch_threads", where);
  setup.libtorch = Field<std::string>(line, "libtorch", where);
  setup.mujoco = Field<std::string>(line, "mujoco", where);
  setup.xgboost = Field<std::string>(line, "xgboost", where);
  setup.onednn = OptionalText(line, "onednn", where);
  setup.device = Field<std::string>(line, "device", where);
  setup.python_functions = OptionalText(line, "python_functions", where);
  session.note = OptionalText(line, "note", where);
  return session;
}

// The sessions of `whole_lines`, the whole lines of `file`.
std::vector<RunSession> ParseSessions(const std::string& whole_lines, const fs::path& file) {
  std::vector<RunSession> sessions;
  std::istringstream lines(whole_lines);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const std::string where = fmt::format("'{}' line {}", file.string(), number);
    sessions.push_back(ParseSession(line, where));
    const std::string id = RunIdOf(sessions);
    Require(sessions.back().run_id.empty() || sessions.back().run_id == id,
            "{}: run '{}' where the earlier lines have run '{}': expected the sessions of one "
            "run (the file was edited or joined from two runs)",
            where, sessions.back().run_id, id);
  }
  return sessions;
}

// 128 bits from the OS's entropy as 32 hex digits: an identity, never a seed of any result.
std::string NewRunId() {
  std::random_device entropy;
  std::string id;
  for (int i = 0; i < 4; ++i) id += fmt::format("{:08x}", static_cast<std::uint32_t>(entropy()));
  return id;
}

std::string ValueText(const nlohmann::ordered_json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

}  // namespace

bool NumericsSetup::operator==(const NumericsSetup& other) const {
  return SetupChanges(*this, other).empty();
}

std::vector<std::string> SetupChanges(const NumericsSetup& before, const NumericsSetup& after) {
  const nlohmann::ordered_json then = SetupJson(before);
  const nlohmann::ordered_json now = SetupJson(after);
  std::vector<std::string> changes;
  for (const auto& [key, value] : then.items()) {
    if (value == now.at(key)) continue;
    changes.push_back(
        fmt::format("{} '{}' -> '{}'", key, ValueText(value), ValueText(now.at(key))));
  }
  return changes;
}

std::string DescribeSetup(const NumericsSetup& setup) {
  return fmt::format(
      "cmbrl {}; CPU '{}' ({}), OpenBLAS kernels '{}' with {} thread(s), LibTorch {} with {} "
      "thread(s); MuJoCo {}, XGBoost {}, oneDNN {}; device {}",
      setup.cmbrl, setup.cpu, setup.cpu_isa.empty() ? "ISA not recorded" : setup.cpu_isa,
      setup.blas_core, setup.blas_threads, setup.libtorch, setup.torch_threads, setup.mujoco,
      setup.xgboost, setup.onednn.empty() ? "none" : setup.onednn, setup.device) +
         (setup.python_functions.empty()
              ? std::string()
              : fmt::format("; Python {}", setup.python_functions));
}

std::string RunIdOf(const std::vector<RunSession>& sessions) {
  for (const RunSession& session : sessions) {
    if (!session.run_id.empty()) return session.run_id;
  }
  return "";
}

std::vector<RunSession> ReadRunSessions(const RunDirectory& run) {
  const fs::path file = run.sessions_file();
  return ParseSessions(ReadWholeLines(file), file);
}

std::vector<std::string> RecordRunSession(const RunDirectory& run, std::int64_t steps_done,
                                          const NumericsSetup& setup, const std::string& note) {
  const fs::path file = run.sessions_file();
  const std::string whole_lines = ReadWholeLines(file);
  const std::vector<RunSession> before = ParseSessions(whole_lines, file);
  if (fs::exists(file)) {
    std::error_code error;
    fs::resize_file(file, whole_lines.size(), error);
    Require(!error, "could not drop the unfinished last line of '{}': {}", file.string(),
            error.message());
  }
  RunSession session;
  session.number = before.empty() ? 1 : before.back().number + 1;
  session.run_id = RunIdOf(before);
  if (session.run_id.empty()) session.run_id = NewRunId();
  session.began = UtcTimestamp();
  session.steps_done = steps_done;
  session.setup = setup;
  session.note = note;
  AppendToFile(file, SessionJson(session).dump() + "\n");
  return before.empty() ? std::vector<std::string>() : SetupChanges(before.back().setup, setup);
}

}  // namespace cmbrl

#include "cmbrl/run/run_directory.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"
#include "cmbrl/run/learner_state.h"

namespace cmbrl {
namespace fs = std::filesystem;
namespace {

constexpr const char* kManifest = "manifest.json";
// v1 covers progress.csv and the checkpoint's files; v2 (v0.7) also config.yaml, sessions.jsonl
// and itself.
constexpr const char* kManifestFormatV1 = "cmbrl-checkpoint-v1";
constexpr const char* kManifestFormat = "cmbrl-checkpoint-v2";

fs::path TmpCheckpoint(const RunDirectory& run) { return run.root() / "checkpoint.tmp"; }
fs::path OldCheckpoint(const RunDirectory& run) { return run.root() / "checkpoint.old"; }

std::uint32_t Crc(std::uint32_t crc, const char* data, size_t size) {
  return static_cast<std::uint32_t>(
      crc32_z(crc, reinterpret_cast<const Bytef*>(data), static_cast<z_size_t>(size)));
}

// The header and the first `rows` rows of progress.csv, and how many rows it holds in all.
struct ProgressPrefix {
  std::string text;
  std::int64_t rows_in_file = 0;
};

ProgressPrefix ReadProgressPrefix(const RunDirectory& run, std::int64_t rows) {
  std::ifstream in = OpenToRead(run.progress_file());
  ProgressPrefix prefix;
  std::string line;
  for (std::int64_t i = -1; std::getline(in, line); ++i) {
    if (i < rows) prefix.text += line + "\n";
    if (i >= 0) ++prefix.rows_in_file;
  }
  return prefix;
}

std::uint32_t TextCrc(const std::string& text) {
  return Crc(Crc(0, nullptr, 0), text.data(), text.size());
}

// The first `lines` whole lines of sessions.jsonl, and how many whole lines it holds in all
// (a stop mid-write may leave a last line unfinished: it is not counted).
struct SessionsPrefix {
  std::string text;
  std::int64_t lines_in_file = 0;
  bool exists = false;
};

SessionsPrefix ReadSessionsPrefix(const RunDirectory& run, std::int64_t lines) {
  SessionsPrefix prefix;
  if (!fs::exists(run.sessions_file())) return prefix;
  prefix.exists = true;
  std::istringstream whole(ReadWholeLines(run.sessions_file()));
  std::string line;
  while (std::getline(whole, line)) {
    if (prefix.lines_in_file < lines) prefix.text += line + "\n";
    ++prefix.lines_in_file;
  }
  return prefix;
}

// A manifest's JSON without its own checksum, as the checksum is taken over it.
std::uint32_t ManifestCrc(nlohmann::ordered_json json) {
  json.erase("manifest_crc32");
  return TextCrc(json.dump());
}

void WriteManifest(const fs::path& folder, const CheckpointManifest& m) {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const CheckpointManifest::File& f : m.files) {
    files.push_back({{"name", f.name}, {"size", f.size}, {"crc32", f.crc}});
  }
  nlohmann::ordered_json json = {{"format", kManifestFormat},
                                 {"rows", m.rows},
                                 {"elapsed_seconds", m.elapsed_seconds},
                                 {"progress_crc32", m.progress_crc},
                                 {"config_crc32", m.config_crc},
                                 {"sessions", m.sessions},
                                 {"sessions_crc32", m.sessions_crc},
                                 {"files", files}};
  if (m.steps_done) json["steps_done"] = *m.steps_done;
  if (m.cpu_seconds) json["cpu_seconds"] = *m.cpu_seconds;
  json["manifest_crc32"] = ManifestCrc(json);
  WriteFile(folder / kManifest, json.dump(2) + "\n");
}

CheckpointManifest ReadManifest(const fs::path& path) {
  CheckpointManifest m;
  try {
    std::ifstream in(path);
    const nlohmann::ordered_json json = nlohmann::ordered_json::parse(in);
    const nlohmann::ordered_json format = json.at("format");
    m.covers_run = format == kManifestFormat;
    Require(m.covers_run || format == kManifestFormatV1, "format is {}: expected \"{}\"",
            format.dump(), kManifestFormat);
    if (m.covers_run) {
      Require(json.at("manifest_crc32").get<std::uint32_t>() == ManifestCrc(json),
              "its checksum does not match its content: it was edited");
      m.config_crc = json.at("config_crc32").get<std::uint32_t>();
      m.sessions = json.at("sessions").get<std::int64_t>();
      m.sessions_crc = json.at("sessions_crc32").get<std::uint32_t>();
    }
    m.rows = json.at("rows").get<std::int64_t>();
    m.elapsed_seconds = json.at("elapsed_seconds").get<double>();
    m.progress_crc = json.at("progress_crc32").get<std::uint32_t>();
    for (const nlohmann::ordered_json& f : json.at("files")) {
      m.files.push_back({f.at("name").get<std::string>(), f.at("size").get<std::uintmax_t>(),
                         f.at("crc32").get<std::uint32_t>()});
    }
    Require(m.rows >= 0, "rows is {}: expected 0 or more", m.rows);
    if (json.contains("steps_done")) {
      m.steps_done = json.at("steps_done").get<std::int64_t>();
      Require(*m.steps_done >= 0, "steps_done is {}: expected 0 or more", *m.steps_done);
    }
    if (json.contains("cpu_seconds")) {
      m.cpu_seconds = json.at("cpu_seconds").get<double>();
      Require(std::isfinite(*m.cpu_seconds) && *m.cpu_seconds >= 0.0,
              "cpu_seconds is {}: expected a number of seconds, 0 or more", *m.cpu_seconds);
    }
  } catch (const nlohmann::json::exception& error) {
    Fail("'{}' is damaged: {}", path.string(), error.what());
  } catch (const Error& error) {
    Fail("'{}' is damaged: {}", path.string(), error.what());
  }
  return m;
}

// A checkpoint of v0.2 has no manifest; its state.json holds the rows and seconds it covered.
CheckpointManifest LegacyManifest(const fs::path& state_path) {
  CheckpointManifest m;
  try {
    std::ifstream in(state_path);
    const nlohmann::json state = nlohmann::json::parse(in);
    // A state.json of v0.3 or later keeps no rows: its checkpoint's manifest.json was deleted.
    Require(state.contains("rows"),
            "'{}' is missing: the checkpoint was written by a version that writes one (its "
            "state.json keeps no rows), so it was deleted; the run cannot be checked",
            (state_path.parent_path() / kManifest).string());
    m.rows = state.at("rows").get<std::int64_t>();
    m.elapsed_seconds = state.at("elapsed_seconds").get<double>();
  } catch (const nlohmann::json::exception& error) {
    Fail("'{}' is damaged: {}", state_path.string(), error.what());
  }
  return m;
}

}  // namespace

RunDirectory::RunDirectory(fs::path root) : root_(std::move(root)) {}

bool RunDirectory::HoldsRun() const { return fs::exists(config_file()); }

void RunDirectory::RefuseExistingRun() const {
  Require(!HoldsRun(),
          "'{}' already holds a run: resume it with --resume, or choose another directory",
          root_.string());
}

RunDirectory RunDirectory::Create(const fs::path& root, const std::string& config_yaml,
                                  const std::string& progress_header,
                                  const std::function<void()>& claim) {
  RunDirectory run(root);
  run.RefuseExistingRun();
  std::error_code error;
  if (root.has_parent_path()) fs::create_directories(root.parent_path(), error);
  // Whether this process made the directory: mkdir is atomic, an earlier exists() is not.
  const bool made_root = fs::create_directory(root, error);
  Require(!error, "cannot create the run directory '{}': {}", root.string(), error.message());
  // A process refused the run's lock touches nothing: the directory may be another's live run.
  claim();
  run.RefuseExistingRun();  // another process may have made one before this one locked it
  std::vector<fs::path> made;
  try {
    made.push_back(run.progress_file());
    WriteFile(run.progress_file(), progress_header + "\n");
    made.push_back(run.first_checkpoint_pending_file());
    WriteFile(run.first_checkpoint_pending_file(),
              "this run's first checkpoint is not written yet: rows before it are dropped on "
              "resume\n");
    made.push_back(run.config_tmp_file());
    made.push_back(run.config_file());
    run.ReplaceConfig(config_yaml);
  } catch (...) {
    // The lock file stays unless the whole directory goes: removing it while a process may
    // have it open would let two processes lock two different files.
    if (made_root) {
      fs::remove_all(root, error);
    } else {
      for (const fs::path& path : made) fs::remove(path, error);
    }
    throw;
  }
  return run;
}

void RunDirectory::ReplaceConfig(const std::string& config_yaml) const {
  const fs::path tmp = config_tmp_file();
  WriteFile(tmp, config_yaml);
  std::error_code error;
  fs::rename(tmp, config_file(), error);
  Require(!error, "cannot replace '{}': {}", config_file().string(), error.message());
}

std::uint32_t FileCrc(const fs::path& path) {
  std::ifstream in = OpenToRead(path, /*binary=*/true);
  std::uint32_t crc = Crc(0, nullptr, 0);
  std::vector<char> block(1 << 20);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    crc = Crc(crc, block.data(), static_cast<size_t>(in.gcount()));
  }
  Require(in.eof(), "cannot read '{}'", path.string());
  return crc;
}

namespace {

// What a manifest records of the run's own files as they are now: config.yaml whole, and every
// whole line of sessions.jsonl.
void CoverRunFiles(const RunDirectory& run, CheckpointManifest& manifest) {
  manifest.covers_run = true;
  manifest.config_crc = FileCrc(run.config_file());
  const SessionsPrefix sessions =
      ReadSessionsPrefix(run, std::numeric_limits<std::int64_t>::max());
  manifest.sessions = sessions.lines_in_file;
  manifest.sessions_crc = TextCrc(sessions.text);
}

// Adds the manifest to a filled checkpoint.tmp, then swaps it in for checkpoint/ (and a new
// config.yaml in from config.yaml.tmp when `new_config`), so that a stop at any moment leaves a
// whole old or a whole new checkpoint (RecoverInterruptedCheckpoint finishes the rest).
void SwapInCheckpoint(const RunDirectory& run, const fs::path& tmp,
                      const CheckpointManifest& manifest, bool new_config) {
  WriteManifest(tmp, manifest);
  const fs::path old = OldCheckpoint(run), final_dir = run.checkpoint_dir();
  fs::remove_all(old);
  if (fs::exists(final_dir)) fs::rename(final_dir, old);
  fs::rename(tmp, final_dir);
  if (new_config) fs::rename(run.config_tmp_file(), run.config_file());
  fs::remove_all(old);
}

}  // namespace

void WriteCheckpoint(const RunDirectory& run, std::int64_t rows, double elapsed_seconds,
                     const std::function<void(const fs::path&, const fs::path&)>& write,
                     std::optional<std::int64_t> steps_done, std::optional<double> cpu_seconds) {
  const fs::path tmp = TmpCheckpoint(run);
  const fs::path final_dir = run.checkpoint_dir();
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  try {
    write(tmp, fs::exists(final_dir) ? final_dir : fs::path());
    CheckpointManifest manifest;
    manifest.rows = rows;
    manifest.elapsed_seconds = elapsed_seconds;
    manifest.steps_done = steps_done;
    manifest.cpu_seconds = cpu_seconds;
    manifest.progress_crc = TextCrc(ReadProgressPrefix(run, rows).text);
    CoverRunFiles(run, manifest);
    std::vector<fs::path> files;
    for (const fs::directory_entry& entry : fs::directory_iterator(tmp)) {
      files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
      manifest.files.push_back({file.filename().string(), fs::file_size(file), FileCrc(file)});
    }
    SwapInCheckpoint(run, tmp, manifest, /*new_config=*/false);
    std::error_code ignored;  // a mark left by a stop here is ignored beside a checkpoint
    fs::remove(run.first_checkpoint_pending_file(), ignored);
  } catch (const Error& error) {
    // A full disk: the last whole checkpoint stays, and the half-written one frees its space.
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    if (fs::exists(final_dir)) {
      Fail("{} (the run's last whole checkpoint is kept: free space, then resume it)",
           error.what());
    }
    Fail("{} (the run has no checkpoint yet: free space, then resume it; it starts again from its "
         "beginning)",
         error.what());
  }
}

void ReplaceCheckpointedConfig(const RunDirectory& run, const std::string& config_yaml) {
  const std::optional<CheckpointManifest> checkpoint = VerifiedCheckpoint(run, /*files=*/false);
  if (!checkpoint || !checkpoint->covers_run) {
    run.ReplaceConfig(config_yaml);  // nothing (or a v1 manifest) records the config
    return;
  }
  WriteFile(run.config_tmp_file(), config_yaml);
  // The same checkpoint, its files hard-linked (never rewritten), under a manifest that records
  // the new config.yaml.
  const fs::path tmp = TmpCheckpoint(run);
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  CheckpointManifest manifest = *checkpoint;
  for (const CheckpointManifest::File& file : manifest.files) {
    std::error_code error;
    fs::create_hard_link(run.checkpoint_dir() / file.name, tmp / file.name, error);
    if (error) fs::copy_file(run.checkpoint_dir() / file.name, tmp / file.name);
  }
  manifest.config_crc = FileCrc(run.config_tmp_file());  // sessions stay as the checkpoint's
  SwapInCheckpoint(run, tmp, manifest, /*new_config=*/true);
}

std::int64_t ProgressRowsInFile(const RunDirectory& run) {
  return ReadProgressPrefix(run, 0).rows_in_file;
}

void RecoverInterruptedCheckpoint(const RunDirectory& run) {
  if (!fs::exists(run.checkpoint_dir()) && fs::exists(OldCheckpoint(run))) {
    fs::rename(OldCheckpoint(run), run.checkpoint_dir());
  }
  fs::remove_all(TmpCheckpoint(run));
  // A stop inside ReplaceCheckpointedConfig: its config.yaml.tmp goes in when the checkpoint in
  // place already records it, and is dropped otherwise (as Create's would be).
  const fs::path config_tmp = run.config_tmp_file();
  if (!fs::exists(config_tmp)) return;
  const fs::path manifest_file = run.checkpoint_dir() / kManifest;
  if (fs::exists(manifest_file)) {
    const CheckpointManifest manifest = ReadManifest(manifest_file);
    if (manifest.covers_run && manifest.config_crc == FileCrc(config_tmp) &&
        manifest.config_crc != FileCrc(run.config_file())) {
      fs::rename(config_tmp, run.config_file());
      return;
    }
  }
  fs::remove(config_tmp);
}

fs::path LastCheckpointDir(const RunDirectory& run) {
  // A stop between the two renames of WriteCheckpoint leaves only checkpoint.old.
  if (!fs::exists(run.checkpoint_dir()) && fs::exists(OldCheckpoint(run))) {
    return OldCheckpoint(run);
  }
  return run.checkpoint_dir();
}

std::optional<CheckpointManifest> VerifiedCheckpoint(const RunDirectory& run, bool files) {
  const fs::path folder = LastCheckpointDir(run);
  if (!fs::exists(folder)) {
    const std::int64_t rows = ReadProgressPrefix(run, 0).rows_in_file;
    Require(rows == 0 || fs::exists(run.first_checkpoint_pending_file()),
            "'{}' has {} rows but the run has no checkpoint ('{}' is missing): its parts "
            "disagree; start a new run",
            run.progress_file().string(), rows, folder.string());
    return std::nullopt;
  }
  CheckpointManifest manifest;
  if (fs::exists(folder / kManifest)) {
    manifest = ReadManifest(folder / kManifest);
    for (const CheckpointManifest::File& file : manifest.files) {
      if (!files) break;
      const fs::path path = folder / file.name;
      Require(fs::exists(path), "'{}' is missing: the checkpoint's manifest lists it",
              path.string());
      Require(fs::file_size(path) == file.size && FileCrc(path) == file.crc,
              "'{}' differs from the file the checkpoint wrote (size or checksum): it was "
              "changed or damaged",
              path.string());
    }
  } else {
    const fs::path state = folder / kLearnerStateFile;
    Require(fs::exists(state),
            "'{}' holds neither {} nor {}: the checkpoint is incomplete or was changed",
            folder.string(), kManifest, kLearnerStateFile);
    manifest = LegacyManifest(state);  // written by v0.2: nothing to check the files against
    return manifest;
  }
  if (manifest.covers_run) {
    Require(FileCrc(run.config_file()) == manifest.config_crc,
            "'{}' differs from the configuration the run's checkpoint recorded: it was edited "
            "(a run's configuration changes only through --resume --steps){}",
            run.config_file().string(),
            fs::exists(run.config_tmp_file())
                ? "; or a budget change was interrupted: resume the run to finish it"
                : "");
  }
  const ProgressPrefix prefix = ReadProgressPrefix(run, manifest.rows);
  Require(prefix.rows_in_file >= manifest.rows,
          "'{}' has {} rows but the checkpoint covers {}: it was shortened",
          run.progress_file().string(), prefix.rows_in_file, manifest.rows);
  Require(TextCrc(prefix.text) == manifest.progress_crc,
          "'{}' differs in its first {} rows from what the checkpoint recorded: it was edited",
          run.progress_file().string(), manifest.rows);
  if (manifest.covers_run) {
    const SessionsPrefix sessions = ReadSessionsPrefix(run, manifest.sessions);
    Require(sessions.exists || manifest.sessions == 0,
            "'{}' is missing: the run's checkpoint covers its first {} session(s)",
            run.sessions_file().string(), manifest.sessions);
    Require(sessions.lines_in_file >= manifest.sessions &&
                TextCrc(sessions.text) == manifest.sessions_crc,
            "'{}' differs in its first {} line(s) from what the checkpoint recorded: it was "
            "edited or shortened",
            run.sessions_file().string(), manifest.sessions);
  }
  return manifest;
}

namespace {

std::string RunNameStem(const std::string& task, const std::string& method) {
  std::string stem = task + "-" + method;
  std::transform(stem.begin(), stem.end(), stem.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return stem;
}

}  // namespace

std::string SweepRunName(const std::string& task, const std::string& method,
                         const std::string& setting, std::uint64_t seed) {
  return fmt::format("{}{}{}-s{}", RunNameStem(task, method), setting.empty() ? "" : "-", setting,
                     seed);
}

std::string SettingWord(const std::string& key, const std::string& value) {
  std::string word;
  for (const char c : value) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_') {
      word += c;
    } else if (c == ',') {
      word += 'x';
    } else if (c != ' ' && c != '[' && c != ']') {
      word += '_';
    }
  }
  return fmt::format("{}={}", key.substr(key.rfind('.') + 1), word.empty() ? "_" : word);
}

std::string SettingOfRunName(const std::string& name, const std::string& task,
                             const std::string& method, std::uint64_t seed) {
  const std::string prefix = RunNameStem(task, method);
  const std::string suffix = fmt::format("-s{}", seed);
  if (name.size() < prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return "";
  }
  const std::string middle =
      name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return middle.size() > 1 && middle.front() == '-' ? middle.substr(1) : "";
}

void TruncateProgress(const RunDirectory& run, std::int64_t rows) {
  const std::string kept = ReadProgressPrefix(run, rows).text;
  WriteFile(run.progress_file(), kept);
}

}  // namespace cmbrl

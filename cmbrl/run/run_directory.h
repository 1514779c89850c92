// What a run is on disk (one home for it): the directory's layout, its creation (all or
// nothing), its checkpoints (written whole, swapped in atomically) and the manifest that lets a
// run know its own state. train, eval, sweep and report all find a run's parts through here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace cmbrl {

// The files of one run directory. Cheap to copy; touches the disk only where a function says so.
// Thread-compatible (no shared state).
class RunDirectory {
 public:
  explicit RunDirectory(std::filesystem::path root);

  const std::filesystem::path& root() const { return root_; }
  // The resolved configuration, every key with its value. Its presence marks a run.
  std::filesystem::path config_file() const { return root_ / "config.yaml"; }
  // One row per unit of work (an MPC episode, a policy-optimisation epoch).
  std::filesystem::path progress_file() const { return root_ / "progress.csv"; }
  // One line per session of the run (its start, each resume): when, and on what setup
  // (run/run_sessions.h).
  std::filesystem::path sessions_file() const { return root_ / "sessions.jsonl"; }
  // The last whole checkpoint; a learner's files and manifest.json.
  std::filesystem::path checkpoint_dir() const { return root_ / "checkpoint"; }
  // Present from the run's creation until its first checkpoint is in place: rows without a
  // checkpoint beside it were written before a first checkpoint that never completed (a full
  // disk, a kill), not left by a checkpoint removed afterwards.
  std::filesystem::path first_checkpoint_pending_file() const {
    return root_ / "checkpoint.pending";
  }

  bool HoldsRun() const;
  // Throws cmbrl::Error naming the directory when it already holds a run.
  void RefuseExistingRun() const;

  // Creates the run directory and runs `claim` (which takes the run's lock) before writing any
  // file; then checks again that no other process made a run there meanwhile, and writes a
  // progress.csv of `progress_header` alone, the first checkpoint's pending mark and config.yaml
  // (written whole, then renamed into place: its presence marks the run). When `claim` or that check throws, nothing is touched
  // (the directory may hold another process's run). When writing fails, whatever this call
  // wrote is removed again, the directory itself included when this call made it. Throws
  // cmbrl::Error when the directory already holds a run or cannot be written.
  static RunDirectory Create(const std::filesystem::path& root, const std::string& config_yaml,
                             const std::string& progress_header,
                             const std::function<void()>& claim);

  // Writes config.yaml whole, then renames it into place (Create's last step, and a resumed run
  // given a new budget). The caller holds the run's lock. Throws cmbrl::Error when it cannot be
  // written.
  void ReplaceConfig(const std::string& config_yaml) const;

  // Where a new config.yaml is written whole before it is renamed into place; a stop may leave
  // it behind (RecoverInterruptedCheckpoint settles it).
  std::filesystem::path config_tmp_file() const { return root_ / "config.yaml.tmp"; }

 private:

  std::filesystem::path root_;
};

// What a checkpoint covers, from its manifest.json: the rows of progress.csv written before it,
// the seconds the run had trained, every file of the checkpoint with its size and CRC-32, and
// (since v0.7) config.yaml and the sessions of sessions.jsonl begun before it. The manifest
// carries a checksum of its own content, so an edited manifest is named as such.
struct CheckpointManifest {
  std::int64_t rows = 0;
  double elapsed_seconds = 0.0;
  std::uint32_t progress_crc = 0;  // of progress.csv's header and first `rows` rows
  struct File {
    std::string name;
    std::uintmax_t size = 0;
    std::uint32_t crc = 0;
  };
  std::vector<File> files;
  // False for a manifest of v0.3-v0.6, which covers neither config.yaml nor sessions.jsonl.
  bool covers_run = false;
  std::uint32_t config_crc = 0;    // of config.yaml
  std::int64_t sessions = 0;       // whole lines of sessions.jsonl written before it
  std::uint32_t sessions_crc = 0;  // of those lines
  // The learner's steps of its budget when it was written: ahead of the rows' steps when it was
  // taken in the middle of a unit of work. Absent from manifests before v0.9.
  std::optional<std::int64_t> steps_done;
  // The CPU seconds the run's sessions had used (ProcessCpuSeconds, for the rows' CpuTime).
  // Absent from manifests written before CpuTime was kept.
  std::optional<double> cpu_seconds;
};

// Writes a checkpoint: `write` fills an empty folder with the learner's files; a manifest for
// them and the first `rows` rows of progress.csv is added; then the folder replaces the old
// checkpoint, so that a stop at any moment leaves either the old or the new one whole. `write`
// may hard-link unchanged files from the previous checkpoint (its second argument; empty path
// when there is none): files of a checkpoint are never rewritten in place. `steps_done`, when
// given, is recorded in the manifest (for readers of progress such as `sweep --status`), and so
// is `cpu_seconds`, the CPU time of the run so far.
void WriteCheckpoint(const RunDirectory& run, std::int64_t rows, double elapsed_seconds,
                     const std::function<void(const std::filesystem::path& folder,
                                              const std::filesystem::path& previous)>& write,
                     std::optional<std::int64_t> steps_done = std::nullopt,
                     std::optional<double> cpu_seconds = std::nullopt);

// Replaces config.yaml of a run that has a checkpoint (a resume given a new budget) together
// with the manifest that records it: both, or (after a stop, once RecoverInterruptedCheckpoint
// has run) neither. The caller holds the run's lock. Throws cmbrl::Error when a file cannot be
// written.
void ReplaceCheckpointedConfig(const RunDirectory& run, const std::string& config_yaml);

// Puts back the checkpoint that a stop between WriteCheckpoint's two renames left as
// checkpoint.old, removes a half-written checkpoint.tmp, and finishes or drops a config.yaml.tmp
// that ReplaceCheckpointedConfig left. Only for the process holding the run's lock.
void RecoverInterruptedCheckpoint(const RunDirectory& run);

// The folder of the run's last checkpoint: checkpoint/, or checkpoint.old where a stop between
// WriteCheckpoint's two renames left only that (what RecoverInterruptedCheckpoint would put
// back). For readers that must not change the run (eval, load_run): they read it in place.
std::filesystem::path LastCheckpointDir(const RunDirectory& run);

// The run's last checkpoint (checkpoint/, or checkpoint.old after a stop between the renames),
// checked against its manifest and progress.csv: every file present
// with its size and checksum, and progress.csv's first `rows` rows those it covered (rows after
// them were written after it and are dropped on resume). nullopt when the run has no checkpoint
// yet, and progress.csv has no rows or its first checkpoint never completed (its pending mark
// is there: the rows are not covered, and a resume drops them). Throws cmbrl::Error naming the
// file that disagrees: an
// edited or deleted manifest.json, a missing or changed file, a config.yaml other than the one
// the checkpoint recorded, a progress.csv or sessions.jsonl shorter than or different from
// what the checkpoint covered, rows without a checkpoint that once was (no pending mark).
// `files` false checks only what the manifest says of progress.csv, not the checkpoint's own
// files (for readers of progress such as reports: a run's model files can be large).
std::optional<CheckpointManifest> VerifiedCheckpoint(const RunDirectory& run, bool files = true);

// The rows progress.csv holds (its header aside), checkpointed or not.
std::int64_t ProgressRowsInFile(const RunDirectory& run);

// Keeps progress.csv's header and its first `rows` rows.
void TruncateProgress(const RunDirectory& run, std::int64_t rows);

// CRC-32 (zlib) of a file's bytes; throws cmbrl::Error naming a file that cannot be read.
std::uint32_t FileCrc(const std::filesystem::path& path);

// The name a sweep gives a run's directory: <task in lower case>-<method>[-<setting>]-s<seed>.
// A setting names the run's values of an experiment's axes ("population=500"; several joined
// by '-'), "" for a run of no axes.
std::string SweepRunName(const std::string& task, const std::string& method,
                         const std::string& setting, std::uint64_t seed);

// One key's word in a setting: the key's last part, '=', its value as a word of a folder name
// ("planning.population", "500" -> "population=500"; "[256, 256]" -> "256x256", other characters
// that a shell or a path would trip on '_').
std::string SettingWord(const std::string& key, const std::string& value);

// The setting of a run named by SweepRunName, read back from its name with its own task, method
// and seed; "" for a run of no axes, or a name not of that form (a run made by hand).
std::string SettingOfRunName(const std::string& name, const std::string& task,
                             const std::string& method, std::uint64_t seed);

}  // namespace cmbrl

// A learner's small state in its checkpoint (counters, generators' states, figures) as one JSON
// file: written whole, read back with every failure naming the file.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

namespace cmbrl {

// The file of a checkpoint that holds its learner's counters (every learner's, and the v0.2
// checkpoints' only file).
inline constexpr const char* kLearnerStateFile = "state.json";

// Throws cmbrl::Error naming the file when it cannot be written.
void WriteLearnerState(const std::filesystem::path& path, const nlohmann::json& state);

// Parses the file and hands it to `read`. A missing file, invalid JSON, a missing key, a value
// of the wrong type or a cmbrl::Error thrown by `read` becomes one cmbrl::Error: "'<path>' is
// damaged: ...".
void ReadLearnerState(const std::filesystem::path& path,
                      const std::function<void(const nlohmann::json&)>& read);

// A number written as ProgressNumber writes it (text, "nan" for NaN).
double StateNumber(const nlohmann::json& state, const char* key);

}  // namespace cmbrl

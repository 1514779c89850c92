// Writing files so that a full disk, a quota or a vanished folder is an error that names the
// file and the cause ("No space left on device"), never a crash or a file silently cut short;
// and reading back what an interrupted append left whole.
// Every file cmbrl writes goes through here, or is checked as here (Cairo's, XGBoost's).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace cmbrl {

// Writes `bytes` as the whole of `path` (created, or cut to nothing first) and closes it,
// checking every write and the close. Throws cmbrl::Error naming the file and the cause.
void WriteFile(const std::filesystem::path& path, std::string_view bytes);

// Appends `bytes` to `path` (created if missing), checked as WriteFile.
void AppendToFile(const std::filesystem::path& path, std::string_view bytes);

// Closes a stream written piece by piece and throws cmbrl::Error naming `path` and the cause
// when any write or the close failed.
void CloseChecked(std::ofstream& out, const std::filesystem::path& path);

// The text of `path` up to and including its last newline: what an append stopped mid-line left
// whole (a line without its newline does not count). "" when the file is missing. Throws
// cmbrl::Error naming the file when it exists but cannot be read.
std::string ReadWholeLines(const std::filesystem::path& path);

// `path` opened for reading (binary where asked). Throws cmbrl::Error naming the file and why it
// cannot be read: missing ("does not exist"), or the system's cause (a folder, no permission).
std::ifstream OpenToRead(const std::filesystem::path& path, bool binary = false);

// "could not write '<path>': <cause>", the cause from errno (the last failed call's).
[[noreturn]] void FailToWrite(const std::filesystem::path& path);

}  // namespace cmbrl

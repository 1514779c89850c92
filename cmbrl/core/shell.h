// Words for a shell: the commands cmbrl prints for a person to paste (a resume hint, a report's
// "Made by" line) and the scripts it writes (a sweep's slurm.sh).
#pragma once

#include <string>

namespace cmbrl {

// `word` in single quotes, any single quote in it written '\'': one word for any POSIX shell.
inline std::string ShellQuote(const std::string& word) {
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// `word` as it is when a shell reads it as one word unchanged (letters, digits and _ - . / : = @
// % + ,), else ShellQuote(word): paths with spaces, quotes or other characters paste safely.
inline std::string ShellWord(const std::string& word) {
  if (word.empty()) return "''";
  for (const char c : word) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       std::string("_-./:=@%+,").find(c) != std::string::npos;
    if (!plain) return ShellQuote(word);
  }
  return word;
}

}  // namespace cmbrl

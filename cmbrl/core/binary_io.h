// Little helpers for the library's binary files (buffers, checkpoints): raw values in native
// byte order behind a tag and a version, read back with checks that name the file.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"

namespace cmbrl {

class BinaryWriter {
 public:
  BinaryWriter(const std::string& path, const std::string& tag)
      : path_(path), out_(path, std::ios::binary) {
    Require(static_cast<bool>(out_), "cannot write '{}'", path);
    Write(tag);
  }
  template <typename T>
  void Write(const T& value) {
    out_.write(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void Write(const std::string& text) {
    Write<std::uint64_t>(text.size());
    out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  }
  template <typename T>
  void Write(const std::vector<T>& values) {
    Write<std::uint64_t>(values.size());
    out_.write(reinterpret_cast<const char*>(values.data()),
               static_cast<std::streamsize>(values.size() * sizeof(T)));
  }
  // Flushes and reports a failed write, naming the file and the cause.
  void Close() { CloseChecked(out_, path_); }

 private:
  std::string path_;
  std::ofstream out_;
};

class BinaryReader {
 public:
  BinaryReader(const std::string& path, const std::string& tag)
      : path_(path), in_(path, std::ios::binary) {
    Require(static_cast<bool>(in_), "cannot open '{}'", path);
    const std::string found = Read<std::string>();
    Require(found == tag, "'{}' is not a {} file", path, tag);
  }
  template <typename T>
  T Read() {
    T value{};
    if constexpr (std::is_same_v<T, std::string>) {
      const auto size = Read<std::uint64_t>();
      Require(size < (1ULL << 32), "'{}' is damaged", path_);
      value.resize(size);
      in_.read(value.data(), static_cast<std::streamsize>(size));
    } else {
      in_.read(reinterpret_cast<char*>(&value), sizeof(T));
    }
    Require(static_cast<bool>(in_), "'{}' ends early: the file is damaged", path_);
    return value;
  }
  template <typename T>
  std::vector<T> ReadVector() {
    const auto size = Read<std::uint64_t>();
    Require(size < (1ULL << 34) / sizeof(T), "'{}' is damaged", path_);
    std::vector<T> values(size);
    in_.read(reinterpret_cast<char*>(values.data()),
             static_cast<std::streamsize>(size * sizeof(T)));
    Require(static_cast<bool>(in_), "'{}' ends early: the file is damaged", path_);
    return values;
  }

 private:
  std::string path_;
  std::ifstream in_;
};

}  // namespace cmbrl

// Little helpers for the library's binary files (buffers, checkpoints) and states held as bytes:
// raw values in native byte order behind a tag and a version, read back with checks that name
// the file or the bytes.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
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

// The same raw values in memory: a state handed around as bytes (an environment's, for
// pickling). `what` names the bytes in errors.
class ByteWriter {
 public:
  template <typename T>
  void Write(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void WriteBytes(const void* data, size_t size) {
    Write<std::uint64_t>(size);
    bytes_.append(static_cast<const char*>(data), size);
  }
  void Write(const std::string& text) { WriteBytes(text.data(), text.size()); }
  std::string Take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
  template <typename T>
  T Read() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value{};
    std::memcpy(&value, Take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  // A block WriteBytes wrote, which must hold `expected` bytes.
  std::string_view ReadBytes(size_t expected) {
    const auto size = Read<std::uint64_t>();
    Require(size == expected, "{} is damaged or of another kind: a block of {} bytes where {} "
            "were expected", what_, size, expected);
    return Take(expected);
  }
  std::string ReadString() { return std::string(Take(Read<std::uint64_t>())); }
  // Refuses bytes left over: they belong to another format.
  void ExpectEnd() const {
    Require(bytes_.empty(), "{} is damaged: {} bytes more than expected", what_, bytes_.size());
  }

 private:
  std::string_view Take(std::uint64_t size) {
    Require(size <= bytes_.size(), "{} is damaged: it ends early", what_);
    const std::string_view part = bytes_.substr(0, size);
    bytes_.remove_prefix(size);
    return part;
  }
  std::string_view bytes_;
  std::string what_;
};

}  // namespace cmbrl

#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>

namespace trainsim::io {

/// Writes `bytes` to `path` atomically: into a hidden temporary file in the same folder, then
/// renamed over `path`, so readers (and a run killed part-way) see the old file or the whole
/// new one, never a part. Throws IoError naming the file and the system's reason (read-only
/// folder, disk full, ...); the temporary file is removed on failure.
void writeFileAtomic(const std::filesystem::path& path, std::string_view bytes, bool sync = false);

/// A file written atomically in pieces, for outputs too large to hold in memory (a 1000 km
/// trajectory.csv): write() goes through a buffer into a hidden temporary file in the same
/// folder, commit() renames it over `path`. Destroyed without commit() (an exception, a
/// cancelled plan), it removes the temporary file, so `path` is the old file or the whole new
/// one, never a part. Throws IoError naming `path` and the system's reason.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view bytes);
  /// Flushes, optionally fsyncs, closes and renames the file into place.
  void commit(bool sync = false);
  const std::filesystem::path& path() const { return path_; }

 private:
  void flush();
  std::filesystem::path path_;
  std::filesystem::path temp_;
  int fd_ = -1;
  std::string buffer_;
};

/// Reads a whole file; throws IoError naming it on failure, or when it holds more than
/// `max_bytes` (an input that size is a mistake, not data).
std::string readFile(const std::filesystem::path& path,
                     std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

/// Throws RuntimeError naming `file` if `text` holds a value printed from a non-finite double
/// ("nan", "inf", "-nan", "-inf" as a whole field of a CSV row or JSON array): the writers
/// call it on what they format, so no NaN or infinity reaches an output file.
void requireFinite(std::string_view text, std::string_view file);

/// True for the hidden temporary files writeFileAtomic() creates (left behind only by a
/// process that was killed).
bool isAtomicTemporary(const std::filesystem::path& path);

/// A file that only grows (CSV streams, times.txt), written through a buffer. flush() pushes
/// the buffer to the file and returns the file's length, which a checkpoint records so that
/// --resume can cut the file back to the last complete frame.
class AppendFile {
 public:
  /// Opens `path` for appending. If `keep_bytes` is given the file must exist and is first
  /// truncated to that length (resume); otherwise it is created empty. Throws IoError.
  AppendFile(std::filesystem::path path, std::int64_t keep_bytes = -1);
  ~AppendFile();
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  /// Appends text (whole lines); RuntimeError if it holds a non-finite value (requireFinite).
  void write(std::string_view text);
  /// Writes the buffer out; returns the length of the file. Throws IoError.
  std::int64_t flush();
  /// Cuts the file back to `length` bytes and drops the buffer (used to undo a failed frame).
  void truncate(std::int64_t length);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::string buffer_;
  std::int64_t written_ = 0;
};

}  // namespace trainsim::io

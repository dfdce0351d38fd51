#include "trainsim/io/file_io.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>

#include "trainsim/core/error.hpp"

namespace trainsim::io {
namespace fs = std::filesystem;
namespace {

constexpr std::string_view kTempMarker = ".tmp.";

void writeAll(int fd, std::string_view bytes, const fs::path& name) {
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      throw IoError(systemErrorMessage("cannot write", name.string(), errno));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

}  // namespace

void requireFinite(std::string_view text, std::string_view file) {
  const auto separator = [](char c) {
    return c == ',' || c == '[' || c == ']' || c == ' ' || c == '\n' || c == '-' || c == '+';
  };
  for (const std::string_view word : {std::string_view("nan"), std::string_view("inf")}) {
    for (std::size_t at = text.find(word); at != std::string_view::npos;
         at = text.find(word, at + 1)) {
      const std::size_t end = at + word.size();
      if ((at == 0 || separator(text[at - 1])) && (end == text.size() || separator(text[end])))
        throw RuntimeError(
            fmt::format("refusing to write a non-finite value ({}) into {}", word, file));
    }
  }
}

bool isAtomicTemporary(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name.front() == '.' && name.find(kTempMarker) != std::string::npos;
}

AtomicFile::AtomicFile(fs::path path)
    : path_(std::move(path)),
      temp_(path_.parent_path() / ("." + path_.filename().string() + std::string(kTempMarker) +
                                   std::to_string(::getpid()))) {
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw IoError(systemErrorMessage("cannot create", path_.string(), errno));
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) {  // not committed
    ::close(fd_);
    ::unlink(temp_.c_str());
  }
}

void AtomicFile::write(std::string_view bytes) {
  buffer_.append(bytes);
  if (buffer_.size() >= (1u << 20))
    flush();
}

void AtomicFile::flush() {
  writeAll(fd_, buffer_, path_);
  buffer_.clear();
}

void AtomicFile::commit(bool sync) {
  flush();
  if (sync && ::fsync(fd_) != 0)
    throw IoError(systemErrorMessage("cannot write", path_.string(), errno));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temp_.c_str());
    throw IoError(systemErrorMessage("cannot write", path_.string(), err));
  }
  if (::rename(temp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    ::unlink(temp_.c_str());
    throw IoError(systemErrorMessage("cannot write", path_.string(), err));
  }
}

void writeFileAtomic(const fs::path& path, std::string_view bytes, bool sync) {
  AtomicFile file(path);
  file.write(bytes);
  file.commit(sync);
}

std::string readFile(const fs::path& path, std::size_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    throw IoError(systemErrorMessage("cannot read", path.string(), errno));
  }
  std::string out;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      const int err = errno;
      ::close(fd);
      throw IoError(systemErrorMessage("cannot read", path.string(), err));
    }
    if (n == 0)
      break;
    out.append(buf, static_cast<std::size_t>(n));
    if (out.size() > max_bytes) {
      ::close(fd);
      throw IoError(
          fmt::format("cannot read {}: it is larger than {} MiB", path.string(), max_bytes >> 20));
    }
  }
  ::close(fd);
  return out;
}

AppendFile::AppendFile(fs::path path, std::int64_t keep_bytes) : path_(std::move(path)) {
  const int flags = O_WRONLY | O_CLOEXEC | (keep_bytes < 0 ? O_CREAT | O_TRUNC : 0);
  fd_ = ::open(path_.c_str(), flags, 0644);
  if (fd_ < 0) {
    throw IoError(systemErrorMessage(keep_bytes < 0 ? "cannot create" : "cannot reopen",
                                     path_.string(), errno));
  }
  if (keep_bytes >= 0) {
    const off_t size = ::lseek(fd_, 0, SEEK_END);
    if (size < keep_bytes) {
      ::close(fd_);
      fd_ = -1;
      throw IoError("cannot resume: " + path_.string() + " is shorter than its checkpoint");
    }
    truncate(keep_bytes);
  }
}

AppendFile::~AppendFile() {
  if (fd_ >= 0)
    ::close(fd_);
}

void AppendFile::write(std::string_view text) {
  requireFinite(text, path_.string());
  buffer_.append(text);
  if (buffer_.size() >= (1u << 20))
    flush();
}

std::int64_t AppendFile::flush() {
  if (!buffer_.empty()) {
    // On failure the file may hold part of the buffer; the caller truncates it back to the
    // last checkpoint, so keep `written_` unchanged and drop the buffer.
    std::string pending;
    pending.swap(buffer_);
    writeAll(fd_, pending, path_);
    written_ += static_cast<std::int64_t>(pending.size());
  }
  return written_;
}

void AppendFile::truncate(std::int64_t length) {
  buffer_.clear();
  if (::ftruncate(fd_, length) != 0 || ::lseek(fd_, length, SEEK_SET) < 0) {
    throw IoError(systemErrorMessage("cannot truncate", path_.string(), errno));
  }
  written_ = length;
}

}  // namespace trainsim::io

#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace trainsim {

/// Root of TrainSim's exceptions. Modules throw these; only an application's `main` catches
/// them, prints `what()` and maps them to an exit code with exitCodeFor().
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Invalid input: a malformed or inconsistent scenario, a bad command-line value, a missing
/// input file. The message names the offending field (JSON path) or file. Exit code 2.
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// An input or output operation failed at run time (disk full, read-only folder, ...). The
/// message names the file and the system's reason. Exit code 1.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A failure while computing (numerical breakdown, violated invariant). Exit code 1.
class RuntimeError : public Error {
 public:
  using Error::Error;
};

/// The run was cancelled on request (Ctrl-C, the studio's cancel button). Exit code 1.
class Cancelled : public Error {
 public:
  using Error::Error;
};

/// Process exit codes shared by every TrainSim application.
enum ExitCode : int { kExitOk = 0, kExitRuntime = 1, kExitInvalidInput = 2 };

/// Exit code for an exception: 2 for ConfigError, 1 for everything else.
int exitCodeFor(const std::exception& error) noexcept;

/// A value from the input as a message should show it: control characters escaped (a message
/// is one line), cut to `max` characters with "..." so a megabyte-long value is not echoed.
std::string messageValue(std::string_view text, std::size_t max = 48);

/// "<what>: <strerror(errno_value)>" for an IoError about `path`.
std::string systemErrorMessage(const std::string& what, const std::string& path, int errno_value);

}  // namespace trainsim

#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace trainsim {

/// How progress of long work is shown.
enum class ProgressMode {
  kAuto,  ///< a bar when standard error is a terminal, nothing otherwise
  kBar,   ///< a one-line bar with rate and ETA on standard error, redrawn in place
  kJson,  ///< one JSON object per line on standard output, for scripts
  kNone,  ///< silent
};

/// Parses "auto", "bar", "json", "none"; throws ConfigError otherwise.
ProgressMode parseProgressMode(std::string_view text);

/// One progress update, as handed to a listener (the studio's progress bar).
struct ProgressUpdate {
  std::string_view stage;
  std::string_view unit;
  std::int64_t done = 0;
  std::int64_t total = 0;
  double fraction = 0.0;
  double rate = 0.0;  ///< units per second of new work
  double elapsed_s = 0.0;
  double eta_s = 0.0;  ///< NaN while unknown
};

/// Reports the progress of a sequence of stages, each with a known amount of work.
/// Updates are rate-limited (at most every 100 ms for the bar, every 500 ms for JSON) except
/// the first and last update of each stage, which are always shown.
///
/// JSON lines look like
///   {"stage":"run","done":120,"total":600,"fraction":0.2,"rate":41.5,"elapsed_s":2.9,"eta_s":11.6}
class ProgressReporter {
 public:
  explicit ProgressReporter(ProgressMode mode, std::FILE* bar_stream = stderr,
                            std::FILE* json_stream = stdout);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// Starts a stage with `total` units of work (`unit` names them: "frames", "samples") of
  /// which `already_done` were done before (a resumed run); the rate counts only new work.
  void begin(std::string_view stage, std::int64_t total, std::string_view unit,
             std::int64_t already_done = 0);
  /// Sets the amount done so far in the current stage.
  void update(std::int64_t done);
  /// Marks the current stage complete.
  void end();

  ProgressMode mode() const { return mode_; }

  /// Also hands every shown update (and, in kNone mode, every update at most each 100 ms plus
  /// the first and last of a stage) to `listener`, on the thread doing the work.
  void setListener(std::function<void(const ProgressUpdate&)> listener) {
    listener_ = std::move(listener);
  }

 private:
  // Not "emit": Qt defines that word as a macro, and the studio includes this header.
  void show(bool force);

  using Clock = std::chrono::steady_clock;
  ProgressMode mode_;
  std::FILE* bar_stream_;
  std::FILE* json_stream_;
  std::string stage_;
  std::string unit_;
  std::int64_t total_ = 0;
  std::int64_t done_ = 0;
  std::int64_t start_done_ = 0;
  Clock::time_point start_;
  Clock::time_point last_emit_;
  bool active_ = false;
  std::function<void(const ProgressUpdate&)> listener_;
};

}  // namespace trainsim

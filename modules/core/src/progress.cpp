#include "trainsim/core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "trainsim/core/error.hpp"

namespace trainsim {

ProgressMode parseProgressMode(std::string_view text) {
  if (text == "auto")
    return ProgressMode::kAuto;
  if (text == "bar")
    return ProgressMode::kBar;
  if (text == "json")
    return ProgressMode::kJson;
  if (text == "none")
    return ProgressMode::kNone;
  throw ConfigError("--progress: '" + std::string(text) + "' is not one of auto, bar, json, none");
}

ProgressReporter::ProgressReporter(ProgressMode mode, std::FILE* bar_stream, std::FILE* json_stream)
    : mode_(mode), bar_stream_(bar_stream), json_stream_(json_stream) {
  if (mode_ == ProgressMode::kAuto) {
    mode_ = isatty(fileno(bar_stream_)) != 0 ? ProgressMode::kBar : ProgressMode::kNone;
  }
}

ProgressReporter::~ProgressReporter() {
  if (active_ && mode_ == ProgressMode::kBar) {
    std::fputc('\n', bar_stream_);  // leave the terminal on a fresh line after an error
  }
}

void ProgressReporter::begin(std::string_view stage, std::int64_t total, std::string_view unit,
                             std::int64_t already_done) {
  stage_ = stage;
  unit_ = unit;
  total_ = std::max<std::int64_t>(total, 0);
  done_ = std::clamp<std::int64_t>(already_done, 0, total_);
  start_done_ = done_;
  start_ = Clock::now();
  active_ = true;
  show(true);
}

void ProgressReporter::update(std::int64_t done) {
  if (!active_)
    return;
  done_ = std::clamp<std::int64_t>(done, 0, total_);
  show(done_ == total_);
}

void ProgressReporter::end() {
  if (!active_)
    return;
  done_ = total_;
  show(true);
  if (mode_ == ProgressMode::kBar) {
    std::fputc('\n', bar_stream_);
    std::fflush(bar_stream_);
  }
  active_ = false;
}

void ProgressReporter::show(bool force) {
  if (mode_ == ProgressMode::kNone && !listener_)
    return;
  const auto now = Clock::now();
  const auto min_gap = mode_ == ProgressMode::kJson ? std::chrono::milliseconds(500)
                                                    : std::chrono::milliseconds(100);
  if (!force && now - last_emit_ < min_gap)
    return;
  last_emit_ = now;

  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction =
      total_ > 0 ? static_cast<double>(done_) / static_cast<double>(total_) : 1.0;
  const double rate = elapsed > 0 ? static_cast<double>(done_ - start_done_) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total_ - done_) / rate : NAN;

  if (listener_)
    listener_(ProgressUpdate{stage_, unit_, done_, total_, fraction, rate, elapsed, eta});
  if (mode_ == ProgressMode::kNone)
    return;
  if (mode_ == ProgressMode::kJson) {
    const std::string eta_text = std::isfinite(eta) ? fmt::format("{:.2f}", eta) : "null";
    fmt::print(json_stream_,
               "{{\"stage\":\"{}\",\"done\":{},\"total\":{},\"fraction\":{:.4f},\"rate\":{:.3f},"
               "\"elapsed_s\":{:.2f},\"eta_s\":{}}}\n",
               stage_, done_, total_, fraction, rate, elapsed, eta_text);
    std::fflush(json_stream_);
    return;
  }
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(std::lround(fraction * kWidth));
  const std::string eta_text =
      std::isfinite(eta)
          ? fmt::format("ETA {:02}:{:02}", static_cast<int>(eta) / 60, static_cast<int>(eta) % 60)
          : std::string("ETA --:--");
  fmt::print(bar_stream_, "\r{:<10} [{:<{}}] {:3.0f}% {}/{} {} {:.1f} {}/s {}\x1b[K", stage_,
             std::string(static_cast<std::size_t>(filled), '#'), kWidth, fraction * 100.0, done_,
             total_, unit_, rate, unit_, eta_text);
  std::fflush(bar_stream_);
}

}  // namespace trainsim
